// The Gaussians training starts from (graphdeco's create_from_pcd): one isotropic Gaussian per
// point, scale = sqrt of the mean squared distance to its 3 nearest neighbours, identity rotation,
// opacity 0.1, SH DC from the point colour and higher coefficients 0.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/io/ply_gaussians.h"

namespace s4d::train {

// points and colors are [P * 3]; colours in [0, 1]. Throws std::invalid_argument when empty,
// mismatched or non-finite.
io::GaussianCloud cloud_from_points(const std::vector<float>& points, const std::vector<float>& colors, int sh_degree);

// The dataset's point cloud when it has one; otherwise `random_points` points uniform in a cube of
// half-size extent around the centre of the training cameras' look-at region (D-NeRF's recipe uses
// [-1.3, 1.3]^3 for scenes of extent ~1.3), with colours uniform in [0, 1].
io::GaussianCloud initial_cloud(const data::Dataset& dataset, int sh_degree, uint32_t random_points, uint32_t seed);

// Mean squared distance of each point to its 3 nearest others ([P * 3] in, [P] out), through a
// uniform grid so that 40k-point clouds take milliseconds.
std::vector<float> mean_sq_dist_3nn(const std::vector<float>& points);

}  // namespace s4d::train
