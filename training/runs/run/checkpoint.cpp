#include "s4d/run/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <utility>
#include <vector>

#include "s4d/splat/gaussian_buffers.h"
#include "s4d/util/atomic_file.h"

namespace s4d::run {

namespace fs = std::filesystem;

namespace {

constexpr size_t kMagicSize = 8;
constexpr char kMagic1[kMagicSize + 1] = "S4DCKPT1";  // no checksums: read unverified
constexpr char kMagic2[kMagicSize + 1] = "S4DCKPT2";  // header and per-array checksums

// The per-Gaussian arrays of a checkpoint in file order, by name and address: the cloud's, then the
// trainer's (`trainer`, one per trainer_array_names()).
template <class Vec>
using ArrayList = std::vector<std::pair<std::string, Vec*>>;

template <class Cloud, class Vec>
ArrayList<Vec> gaussian_arrays(Cloud& cloud, const std::vector<Vec*>& trainer) {
  ArrayList<Vec> out;
  const auto arrays = splat::cloud_arrays(cloud);
  for (splat::Attr a : splat::kCloudAttrs) out.emplace_back(splat::attr_name(a), arrays[a]);
  for (size_t k = 0; k < trainer.size(); ++k) out.emplace_back(trainer_array_names()[k], trainer[k]);
  return out;
}

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

std::string hex64(uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// The whole file: magic, header length, header checksum, header, arrays.
std::string encode(const fs::path& path, const CheckpointRef& checkpoint) {
  const std::vector<std::string>& names = trainer_array_names();
  const bool listed_empty = checkpoint.trainer.empty() && checkpoint.cloud.size() == 0;
  if (!listed_empty && checkpoint.trainer.size() != names.size())
    throw std::invalid_argument("checkpoint " + path.string() + ": " + std::to_string(checkpoint.trainer.size()) +
                                " trainer arrays for " + std::to_string(checkpoint.cloud.size()) + " Gaussians, expected " +
                                std::to_string(names.size()));
  static const std::vector<float> kNone;
  std::vector<const std::vector<float>*> trainer = checkpoint.trainer;
  if (listed_empty) trainer.assign(names.size(), &kNone);
  nlohmann::json header;
  header["meta"] = checkpoint.meta;
  header["sh_degree"] = checkpoint.cloud.sh_degree;
  header["count"] = checkpoint.cloud.size();
  header["arrays"] = nlohmann::json::array();
  std::string body;
  auto add = [&](const std::string& name, const std::vector<float>& values) {
    for (size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        throw std::invalid_argument("checkpoint " + path.string() + ": array '" + name + "' holds a non-finite value at " +
                                    std::to_string(i) + "; refusing to write it");
    const size_t bytes = values.size() * sizeof(float);
    header["arrays"].push_back({{"name", name}, {"floats", values.size()}, {"fnv1a64", hex64(fnv1a64(values.data(), bytes))}});
    body.append(reinterpret_cast<const char*>(values.data()), bytes);
  };
  for (const auto& [name, values] : gaussian_arrays(checkpoint.cloud, trainer)) add(name, *values);
  for (const auto& [name, values] : checkpoint.extra) add(name, values);
  const std::string json = header.dump();
  const uint64_t len = json.size(), sum = fnv1a64(json.data(), json.size());
  std::string file(kMagic2, kMagicSize);
  file.append(reinterpret_cast<const char*>(&len), sizeof len);
  file.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  file += json;
  file += body;
  return file;
}

// Best effort: makes the renames in `dir` durable. Filesystems without directory fsync (EINVAL)
// still have the files themselves fsynced.
void fsync_dir(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

[[noreturn]] void fail_errno(const fs::path& path, const std::string& what) {
  throw std::runtime_error("cannot write " + path.string() + ": " + what + ": " + std::strerror(errno));
}

}  // namespace

const char* stat_name(Stat s) {
  switch (s) {
    case kGradAccum: return "grad_accum";
    case kGradCount: return "grad_count";
    case kMaxRadius: return "max_radius";
    case kStatCount: break;
  }
  throw std::out_of_range("stat_name: no statistic " + std::to_string(static_cast<uint32_t>(s)));
}

const std::vector<std::string>& trainer_array_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (splat::Attr a : splat::kCloudAttrs) {
      out.push_back(std::string(splat::attr_name(a)) + ".adam_m");
      out.push_back(std::string(splat::attr_name(a)) + ".adam_v");
    }
    for (uint32_t k = 0; k < kStatCount; ++k) out.push_back(stat_name(Stat(k)));
    return out;
  }();
  return names;
}

uint64_t fnv1a64(const void* bytes, size_t size) {
  const unsigned char* p = static_cast<const unsigned char*>(bytes);
  uint64_t h = 14695981039346656037ull;
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

void write_checkpoint(const fs::path& path, const CheckpointRef& checkpoint) {
  util::write_file_atomic(path, encode(path, checkpoint));
}

void write_checkpoint_rotating(const fs::path& path, const fs::path& previous, const CheckpointRef& checkpoint, bool rotate) {
  const std::string file = encode(path, checkpoint);  // a non-finite state throws here, before any file changes
  const fs::path fresh = path.string() + ".new";
  util::write_file_atomic(fresh, file);  // complete and fsynced under its own name
  if (rotate && fs::exists(path)) {
    // `path` stays in place until the new file replaces it: `previous` becomes a second name of it.
    const fs::path link = previous.string() + ".new";
    ::unlink(link.c_str());
    if (::link(path.c_str(), link.c_str()) == 0) {
      if (::rename(link.c_str(), previous.c_str()) != 0) fail_errno(previous, "rename");
    } else if (::rename(path.c_str(), previous.c_str()) != 0) {  // no hard links here: `previous` covers the gap
      fail_errno(previous, "rename");
    }
  }
  if (::rename(fresh.c_str(), path.c_str()) != 0) fail_errno(path, "rename");
  fsync_dir(path.parent_path());
}

Checkpoint read_checkpoint(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the checkpoint (missing or unreadable)");
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool v1 = file.size() >= kMagicSize && std::memcmp(file.data(), kMagic1, kMagicSize) == 0;
  const bool v2 = file.size() >= kMagicSize && std::memcmp(file.data(), kMagic2, kMagicSize) == 0;
  if (!v1 && !v2) fail(path, "not a style4d checkpoint");
  // S4DCKPT1 files, written before checksums, load unverified (their arrays are still checked for
  // size and finiteness below).
  const size_t prefix = v1 ? 16 : 24;
  if (file.size() < prefix) fail(path, "truncated header");
  uint64_t len = 0, header_sum = 0;
  std::memcpy(&len, file.data() + 8, sizeof len);
  if (v2) std::memcpy(&header_sum, file.data() + 16, sizeof header_sum);
  if (len > file.size() - prefix) fail(path, "truncated header");
  if (v2 && fnv1a64(file.data() + prefix, len) != header_sum) fail(path, "header: checksum mismatch");
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(file.substr(prefix, len));
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("corrupt header: ") + e.what());
  }
  Checkpoint cp;
  size_t offset = prefix + len, count = 0;
  try {
    cp.meta = header.at("meta");
    cp.cloud.sh_degree = header.at("sh_degree").get<int>();
    count = header.at("count").get<size_t>();
    const nlohmann::json& listed = header.at("arrays");
    cp.trainer.resize(trainer_array_names().size());
    std::vector<std::vector<float>*> trainer;
    for (std::vector<float>& t : cp.trainer) trainer.push_back(&t);
    const auto arrays = gaussian_arrays(cp.cloud, trainer);
    if (listed.size() < arrays.size())
      fail(path, "lists " + std::to_string(listed.size()) + " arrays, expected at least " + std::to_string(arrays.size()));
    for (size_t k = 0; k < listed.size(); ++k) {
      const std::string name = listed[k].at("name").get<std::string>();
      const size_t floats = listed[k].at("floats").get<size_t>();
      if (k < arrays.size() && name != arrays[k].first)
        fail(path, "array " + std::to_string(k) + " is '" + name + "', expected '" + arrays[k].first + "'");
      if (floats > (file.size() - offset) / sizeof(float)) fail(path, "truncated in array '" + name + "'");
      const size_t bytes = floats * sizeof(float);
      if (v2 && listed[k].at("fnv1a64").get<std::string>() != hex64(fnv1a64(file.data() + offset, bytes)))
        fail(path, "array '" + name + "': checksum mismatch");
      std::vector<float>* values = k < arrays.size() ? arrays[k].second : &cp.extra.emplace_back(name, std::vector<float>{}).second;
      values->resize(floats);
      if (bytes > 0) std::memcpy(values->data(), file.data() + offset, bytes);  // an empty vector's data() may be null
      offset += bytes;
      for (size_t i = 0; i < floats; ++i)
        if (!std::isfinite((*values)[i])) fail(path, "array '" + name + "' holds a non-finite value at " + std::to_string(i));
    }
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("malformed header: ") + e.what());
  }
  if (offset != file.size()) fail(path, std::to_string(file.size() - offset) + " unexpected bytes after the arrays");
  const int degree = cp.cloud.sh_degree;
  if (degree < 0 || degree > 3) fail(path, "sh_degree " + std::to_string(degree) + " is not 0..3");
  const uint32_t sh_coeffs = static_cast<uint32_t>((degree + 1) * (degree + 1));
  std::vector<const std::vector<float>*> trainer;
  for (const std::vector<float>& t : cp.trainer) trainer.push_back(&t);
  for (const auto& [name, values] : gaussian_arrays(std::as_const(cp.cloud), trainer)) {
    size_t expected = count;  // a statistic: one float per Gaussian
    for (splat::Attr k : splat::kCloudAttrs)
      if (name.rfind(splat::attr_name(k), 0) == 0) expected = count * splat::attr_floats(k, sh_coeffs);
    if (values->size() != expected)
      fail(path, "array '" + name + "' holds " + std::to_string(values->size()) + " floats, expected " +
                     std::to_string(expected) + " for " + std::to_string(count) + " Gaussians");
  }
  return cp;
}

LoadedCheckpoint read_checkpoint_or_previous(const fs::path& path, const fs::path& previous) {
  std::string problem;
  try {
    return {read_checkpoint(path), path, ""};
  } catch (const std::runtime_error& e) {
    problem = e.what();
  }
  if (!fs::exists(previous)) throw std::runtime_error(problem + " (and there is no previous checkpoint " + previous.string() + ")");
  try {
    return {read_checkpoint(previous), previous, problem};
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(problem + "; the previous checkpoint is unusable too: " + e.what());
  }
}

}  // namespace s4d::run
