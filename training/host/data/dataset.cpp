#include "s4d/data/dataset.h"

#include "dataset_parts.h"

namespace s4d::data {

Dataset load_dataset(const std::filesystem::path& root, const LoadOptions& options) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(root)) detail::fail(root, "not a directory");
  if (fs::exists(root / "poses_bounds.npy")) return load_dynerf(root, options);
  if (fs::exists(root / "transforms_train.json")) return load_dnerf(root, options);
  if (fs::exists(root / "dataset.json")) return load_hypernerf(root, options);
  if (fs::is_directory(root / "sparse" / "0")) return load_colmap(root, options);
  detail::fail(root, "unknown dataset layout: found none of poses_bounds.npy (DyNeRF / Neu3D), transforms_train.json "
                     "(D-NeRF), dataset.json (HyperNeRF / Nerfies), sparse/0/ (COLMAP)");
}

}  // namespace s4d::data
