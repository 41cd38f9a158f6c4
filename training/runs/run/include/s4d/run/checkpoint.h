// The checkpoint file: one file holding a run's Gaussians and every other array a run needs to
// continue or to render, written atomically so that a crash or kill -9 leaves the previous file
// intact. What renders reads it here; the trainer reads and writes its whole state through
// s4d/model/checkpoint.h, on top of this file.
//
// Format S4DCKPT2: "S4DCKPT2", u64 header length, u64 FNV-1a 64 of the header bytes, a JSON header
// (meta, sh_degree, count, and per array its name, float count and "fnv1a64", the FNV-1a 64 of its
// bytes as 16 hex digits, in file order), then the arrays as little-endian float32: the cloud's
// (splat::kCloudAttrs), the trainer's (trainer_array_names()), then any further ones. S4DCKPT1 (no
// header checksum, no array checksums) is still read, unverified. The style files of stage 4
// (style_file.h) use the same container.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/io/ply_gaussians.h"

namespace s4d::run {

using NamedArray = std::pair<std::string, std::vector<float>>;

// Densification statistics (ALGORITHMS.md 2.2), one float per Gaussian each: the trainer keeps them
// (s4d/model/trainable_gaussians.h), and every checkpoint lists them under these names.
enum Stat : uint32_t { kGradAccum, kGradCount, kMaxRadius, kStatCount };
const char* stat_name(Stat s);

// The per-Gaussian arrays every checkpoint lists right after the cloud's, in file order: each cloud
// attribute's two Adam moments ("means.adam_m", "means.adam_v", ...), then the statistics. Their
// values are the trainer's; what only renders passes over them, and a style file, which holds no
// Gaussians, lists them empty.
const std::vector<std::string>& trainer_array_names();

// A checkpoint as read.
struct Checkpoint {
  nlohmann::json meta;  // iteration, stage, rng state, lr scale... (owned by the trainer)
  io::GaussianCloud cloud;
  std::vector<std::vector<float>> trainer;  // one per trainer_array_names(), in that order
  // Further named arrays after those (the deformation field and its Adam moments; a style's arrays).
  std::vector<NamedArray> extra;
};

// A checkpoint to write, by reference: writing copies no array.
struct CheckpointRef {
  const nlohmann::json& meta;
  const io::GaussianCloud& cloud;
  // One per trainer_array_names(), in that order; none: each listed empty (a file of no Gaussians).
  std::vector<const std::vector<float>*> trainer;
  const std::vector<NamedArray>& extra;
};

// FNV-1a 64 of `bytes` (offset basis 14695981039346656037, prime 1099511628211): the checksum of
// checkpoint sections. Any one changed byte changes it (each step is a bijection of the state).
uint64_t fnv1a64(const void* bytes, size_t size);

// Throws std::invalid_argument naming the array and index of the first non-finite value (a
// checkpoint never holds NaN) or when the trainer's arrays are not one per name, std::runtime_error
// when writing fails; the old file stays then.
void write_checkpoint(const std::filesystem::path& path, const CheckpointRef& checkpoint);

// Throws std::runtime_error naming the file and what is wrong: missing, not a checkpoint,
// truncated, a checksum mismatch ("header: checksum mismatch", "array 'means': checksum
// mismatch"), inconsistent array sizes, non-finite values.
Checkpoint read_checkpoint(const std::filesystem::path& path);

// Writes `checkpoint` as `path` and keeps the file it replaces as `previous`, so that one damaged
// file never loses a run. The new file is written to a temporary beside `path` and fsynced; then the
// old `path` becomes `previous` (a hard link renamed over it, or a rename where links fail) and the
// temporary is renamed to `path`; then the directory is fsynced. A crash at any step leaves `path`
// or `previous` complete. rotate = false replaces `path` and leaves `previous` alone (the trainer
// does that once after resuming from `previous` because `path` was damaged: the damaged file must
// not replace the good one).
void write_checkpoint_rotating(const std::filesystem::path& path, const std::filesystem::path& previous,
                               const CheckpointRef& checkpoint, bool rotate = true);

struct LoadedCheckpoint {
  Checkpoint checkpoint;
  std::filesystem::path path;  // the file it came from
  std::string newest_problem;  // empty when `path` is the newest; otherwise why the newest was passed over
};

// Reads `path`, or `previous` when `path` is missing or damaged (newest_problem says why then).
// Throws std::runtime_error when neither loads, with what is wrong with each.
LoadedCheckpoint read_checkpoint_or_previous(const std::filesystem::path& path, const std::filesystem::path& previous);

}  // namespace s4d::run
