#include "s4d/data/dataset.h"

#include "dataset_parts.h"

namespace s4d::data {

Dataset load_dataset(const std::filesystem::path& root, const LoadOptions& options) {
  if (!std::filesystem::is_directory(root)) detail::fail(root, "not a directory");
  if (std::filesystem::exists(root / "poses_bounds.npy")) return load_dynerf(root, options);
  if (std::filesystem::exists(root / "transforms_train.json")) return load_dnerf(root, options);
  detail::fail(root, "unknown dataset layout: found neither poses_bounds.npy (DyNeRF / Neu3D) nor "
                     "transforms_train.json (D-NeRF)");
}

}  // namespace s4d::data
