#include "s4d/protocols/frames_json.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>

#include "s4d/util/atomic_file.h"

namespace s4d::protocols {
namespace {

nlohmann::json frame_json(const ProtocolFrame& f, const std::string& file) {
  const io::CameraView& c = f.camera;
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({c.world_to_cam[4 * r], c.world_to_cam[4 * r + 1], c.world_to_cam[4 * r + 2], c.world_to_cam[4 * r + 3]});
  return {{"index", f.index}, {"time", f.time}, {"file", file}, {"width", c.width}, {"height", c.height},
          {"fx", c.fx},       {"fy", c.fy},     {"cx", c.cx},     {"cy", c.cy},       {"world_to_cam", rows}};
}

// j[key] with a message naming the file and where in it the field was expected.
const nlohmann::json& at(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw std::runtime_error(where + ": no field '" + key + "'");
  return j.at(key);
}

ProtocolFrame frame_from(const nlohmann::json& j, const std::string& where, std::string& file) {
  ProtocolFrame f;
  f.index = at(j, "index", where).get<int>();
  f.time = at(j, "time", where).get<double>();
  file = at(j, "file", where).get<std::string>();
  io::CameraView& c = f.camera;
  c.width = at(j, "width", where).get<int>();
  c.height = at(j, "height", where).get<int>();
  c.fx = at(j, "fx", where).get<double>();
  c.fy = at(j, "fy", where).get<double>();
  c.cx = at(j, "cx", where).get<double>();
  c.cy = at(j, "cy", where).get<double>();
  c.time = f.time;
  const nlohmann::json& rows = at(j, "world_to_cam", where);
  if (!rows.is_array() || rows.size() != 4) throw std::runtime_error(where + ": 'world_to_cam' is not 4 rows");
  for (int r = 0; r < 4; ++r) {
    if (!rows[r].is_array() || rows[r].size() != 4) throw std::runtime_error(where + ": 'world_to_cam' row " + std::to_string(r) + " is not 4 numbers");
    for (int k = 0; k < 4; ++k) c.world_to_cam[4 * r + k] = rows[r][k].get<double>();
  }
  return f;
}

}  // namespace

void write_frames_json(const std::filesystem::path& file, const FramesRecord& record) {
  nlohmann::json seqs = nlohmann::json::array();
  for (const SequenceRecord& s : record.sequences) {
    nlohmann::json frames = nlohmann::json::array();
    for (size_t k = 0; k < s.sequence.frames.size(); ++k)
      frames.push_back(frame_json(s.sequence.frames[k], k < s.files.size() ? s.files[k] : ""));
    seqs.push_back({{"name", s.sequence.name}, {"dir", s.dir}, {"video", s.video}, {"flow", s.flow}, {"frames", frames}});
  }
  const nlohmann::json j = {{"path", record.path}, {"format", record.format}, {"sequences", seqs}};
  util::write_file_atomic(file, j.dump(2) + "\n");
}

FramesRecord read_frames_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  const std::string name = file.string();
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    FramesRecord r{at(j, "path", name).get<std::string>(), at(j, "format", name).get<std::string>(), {}};
    const nlohmann::json& seqs = at(j, "sequences", name);
    for (size_t s = 0; s < seqs.size(); ++s) {
      const std::string where = name + ": sequences[" + std::to_string(s) + "]";
      SequenceRecord rec;
      rec.sequence.name = at(seqs[s], "name", where).get<std::string>();
      rec.dir = at(seqs[s], "dir", where).get<std::string>();
      rec.video = at(seqs[s], "video", where).get<std::string>();
      rec.flow = at(seqs[s], "flow", where).get<bool>();
      const nlohmann::json& frames = at(seqs[s], "frames", where);
      for (size_t k = 0; k < frames.size(); ++k) {
        std::string f;
        rec.sequence.frames.push_back(frame_from(frames[k], where + ".frames[" + std::to_string(k) + "]", f));
        rec.sequence.frames.back().camera.name = rec.sequence.name;
        rec.files.push_back(f);
      }
      r.sequences.push_back(std::move(rec));
    }
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
}

}  // namespace s4d::protocols
