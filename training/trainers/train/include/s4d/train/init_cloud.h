// The Gaussians training starts from (graphdeco's create_from_pcd): one isotropic Gaussian per
// point, scale = sqrt of the mean squared distance to its 3 nearest neighbours, identity rotation,
// opacity 0.1, SH DC from the point colour and higher coefficients 0.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/io/ply_gaussians.h"

namespace s4d::train {

// points and colors are [P * 3]; colours in [0, 1]. Throws std::invalid_argument when empty,
// mismatched or non-finite.
io::GaussianCloud cloud_from_points(const std::vector<float>& points, const std::vector<float>& colors, int sh_degree);

// How a run's Gaussians were initialised (train.json "init").
struct InitReport {
  std::string method;      // "points" (the dataset's point cloud) or "random-frustum"
  std::string file;        // the point cloud file, for "points"
  size_t file_points = 0;  // points in that file
  size_t points = 0;       // Gaussians the run starts from
  double voxel = 0;        // voxel edge the file was downsampled with (0: not downsampled)
  double acceptance = 0;   // random: share of candidates inside enough training frustums
};

// The dataset's point cloud when it has one, voxel-downsampled to at most max_points (4DGaussians'
// downsample_point.py: the voxel grows until the cloud fits; each voxel keeps the mean of its points).
// Otherwise `random_points` points drawn uniformly in a cube of half-size extent around the training
// cameras' look-at point, kept only where most training cameras see them (inside the image, in front
// of the camera): on D-NeRF's sphere of cameras this is the region the object can be in, close to
// the [-1.3, 1.3]^3 its recipe hard-codes; colours uniform in [0, 1].
io::GaussianCloud initial_cloud(const data::Dataset& dataset, int sh_degree, uint32_t random_points, uint32_t max_points,
                                uint32_t seed, InitReport* report = nullptr);

// Means of the points (and colours) in each occupied voxel of edge `voxel`, in first-seen order.
void voxel_downsample(std::vector<float>& points, std::vector<float>& colors, double voxel);

// Mean squared distance of each point to its 3 nearest others ([P * 3] in, [P] out), through a
// uniform grid so that 40k-point clouds take milliseconds.
std::vector<float> mean_sq_dist_3nn(const std::vector<float>& points);

}  // namespace s4d::train
