// Never lose a run, the host-side parts: every checkpoint section is checksummed and a damaged or
// truncated file is refused by name; S4DCKPT1 files still load; the newest and the previous
// checkpoint rotate and reading falls back to the previous; settings are checked by one function
// with one message format; the run lock admits one writer and dies with its holder.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host_state_fixture.h"
#include "s4d/model/checkpoint.h"
#include "s4d/run/run_lock.h"
#include "s4d/run/train_config.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }


model::Checkpoint sample(int iteration) {
  return {{{"iteration", iteration}, {"stage", "static"}},
          test::small_state(12, 1, static_cast<unsigned>(iteration)),
          {{"field.planes", {1, 2, 3, 4}}, {"field.mlp", {5, 6}}, {"field.empty", {}}}};
}

// An S4DCKPT2 file's parts: header length, header JSON and where the arrays begin.
struct Layout {
  uint64_t header_len = 0;
  nlohmann::json header;
  size_t body = 0;
};

Layout layout_of(const std::string& file) {
  Layout l;
  REQUIRE(file.compare(0, 8, "S4DCKPT2") == 0);
  std::memcpy(&l.header_len, file.data() + 8, 8);
  l.header = nlohmann::json::parse(file.substr(24, l.header_len));
  l.body = 24 + l.header_len;
  return l;
}

std::string flip_bit(std::string file, size_t byte, int bit = 3) {
  file[byte] = static_cast<char>(file[byte] ^ (1 << bit));
  return file;
}

int iteration_of(const model::Checkpoint& cp) { return cp.meta.at("iteration").get<int>(); }

}  // namespace

TEST_CASE("a flipped bit in the header or in any array of a checkpoint is refused, naming the damaged section") {
  const fs::path dir = fresh_dir("s4d_ckpt_bits");
  const fs::path good = dir / "good.s4dckpt", bad = dir / "bad.s4dckpt";
  model::write_checkpoint(good, sample(7));
  const std::string file = read_bytes(good);
  const Layout l = layout_of(file);
  size_t offset = l.body, checked = 0;
  for (const nlohmann::json& a : l.header.at("arrays")) {
    const std::string name = a.at("name").get<std::string>();
    const size_t bytes = a.at("floats").get<size_t>() * sizeof(float);
    CHECK(a.at("fnv1a64").get<std::string>().size() == 16);
    if (bytes > 0) {
      CAPTURE(name);
      for (size_t at : {offset, offset + bytes / 2, offset + bytes - 1}) {  // first, middle and last byte
        write_bytes(bad, flip_bit(file, at, static_cast<int>(at % 8)));
        CHECK_THROWS_WITH_AS(model::read_checkpoint(bad), (bad.string() + ": array '" + name + "': checksum mismatch").c_str(),
                             std::runtime_error);
      }
      ++checked;
    }
    offset += bytes;
  }
  CHECK(offset == file.size());
  CHECK(checked == 5 + 2 * splat::kCloudAttrCount + model::kStatCount + 2);  // every non-empty array, the field's too
  // The header: a bit of its JSON, or of its stored checksum.
  const std::string header_error = bad.string() + ": header: checksum mismatch";
  for (size_t at : {size_t{24}, size_t{24} + l.header_len / 2, size_t{24} + l.header_len - 1, size_t{16}, size_t{23}}) {
    CAPTURE(at);
    write_bytes(bad, flip_bit(file, at));
    CHECK_THROWS_WITH_AS(model::read_checkpoint(bad), header_error.c_str(), std::runtime_error);
  }
  CHECK_NOTHROW(model::read_checkpoint(good));  // the untouched file still loads
}

TEST_CASE("a truncated checkpoint is refused at any length") {
  const fs::path dir = fresh_dir("s4d_ckpt_cut");
  model::write_checkpoint(dir / "good.s4dckpt", sample(3));
  const std::string file = read_bytes(dir / "good.s4dckpt");
  const Layout l = layout_of(file);
  for (size_t keep : {size_t{0}, size_t{4}, size_t{8}, size_t{20}, size_t{24}, l.body - 1, l.body, l.body + 5,
                      (l.body + file.size()) / 2, file.size() - 1}) {
    CAPTURE(keep);
    write_bytes(dir / "cut.s4dckpt", file.substr(0, keep));
    CHECK_THROWS_AS(model::read_checkpoint(dir / "cut.s4dckpt"), std::runtime_error);
    try {
      model::read_checkpoint(dir / "cut.s4dckpt");
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      CHECK(what.rfind((dir / "cut.s4dckpt").string() + ": ", 0) == 0);
      CHECK((what.find("truncated") != std::string::npos || (keep < 8 && what.find("not a style4d checkpoint") != std::string::npos)));
    }
  }
}

TEST_CASE("S4DCKPT1 checkpoints, written before checksums, still load") {
  const fs::path dir = fresh_dir("s4d_ckpt_v1");
  const model::Checkpoint cp = sample(5);
  model::write_checkpoint(dir / "v2.s4dckpt", cp);
  const std::string v2 = read_bytes(dir / "v2.s4dckpt");
  Layout l = layout_of(v2);
  for (nlohmann::json& a : l.header["arrays"]) a.erase("fnv1a64");
  const std::string json = l.header.dump();
  const uint64_t len = json.size();
  std::string v1 = "S4DCKPT1";
  v1.append(reinterpret_cast<const char*>(&len), 8);
  v1 += json;
  v1 += v2.substr(l.body);
  write_bytes(dir / "v1.s4dckpt", v1);
  const model::Checkpoint back = model::read_checkpoint(dir / "v1.s4dckpt");
  CHECK(back.meta == cp.meta);
  CHECK(back.state.cloud.means == cp.state.cloud.means);
  CHECK(back.state.v[splat::Attr::sh] == cp.state.v[splat::Attr::sh]);
  CHECK(back.extra == cp.extra);
}

TEST_CASE("checkpoints rotate, and reading falls back to the previous one when the newest is damaged or missing") {
  const fs::path dir = fresh_dir("s4d_ckpt_rotate");
  const fs::path newest = dir / "state.s4dckpt", prev = dir / "state.prev.s4dckpt";
  model::write_checkpoint_rotating(newest, prev, sample(1));
  CHECK(fs::exists(newest));
  CHECK_FALSE(fs::exists(prev));
  model::write_checkpoint_rotating(newest, prev, sample(2));
  model::write_checkpoint_rotating(newest, prev, sample(3));
  CHECK(iteration_of(model::read_checkpoint(newest)) == 3);
  CHECK(iteration_of(model::read_checkpoint(prev)) == 2);
  for (const fs::directory_entry& e : fs::directory_iterator(dir))  // no temporaries left behind
    CHECK_MESSAGE((e.path() == newest || e.path() == prev), e.path().string());

  model::LoadedCheckpoint got = model::read_checkpoint_or_previous(newest, prev);
  CHECK(iteration_of(got.checkpoint) == 3);
  CHECK(got.path == newest);
  CHECK(got.newest_problem.empty());

  // A damaged newest: the previous, and why.
  const std::string good3 = read_bytes(newest);
  write_bytes(newest, flip_bit(good3, layout_of(good3).body + 5));
  got = model::read_checkpoint_or_previous(newest, prev);
  CHECK(iteration_of(got.checkpoint) == 2);
  CHECK(got.path == prev);
  CHECK(got.newest_problem == newest.string() + ": array 'means': checksum mismatch");

  // Written after such a fallback, the damaged newest must not replace the good previous one.
  model::write_checkpoint_rotating(newest, prev, sample(4), /*rotate=*/false);
  CHECK(iteration_of(model::read_checkpoint(newest)) == 4);
  CHECK(iteration_of(model::read_checkpoint(prev)) == 2);

  // A non-finite state is never written and changes neither file.
  model::Checkpoint nan = sample(5);
  nan.state.cloud.quats[2] = NAN;
  CHECK_THROWS_AS(model::write_checkpoint_rotating(newest, prev, nan), std::invalid_argument);
  CHECK(iteration_of(model::read_checkpoint(newest)) == 4);
  CHECK(iteration_of(model::read_checkpoint(prev)) == 2);

  // A missing newest (a crash between renames where hard links fail): the previous.
  fs::remove(newest);
  got = model::read_checkpoint_or_previous(newest, prev);
  CHECK(iteration_of(got.checkpoint) == 2);
  CHECK(got.newest_problem.find(newest.string()) != std::string::npos);

  // Neither loads: both named.
  write_bytes(newest, "S4DCKPT2");
  write_bytes(prev, flip_bit(read_bytes(prev), 30));
  const std::string prev_damage = prev.string() + ": header: checksum mismatch";
  const std::string newest_damage = newest.string() + ": truncated header";
  CHECK_THROWS_WITH_AS(model::read_checkpoint_or_previous(newest, prev), doctest::Contains(prev_damage.c_str()),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(model::read_checkpoint_or_previous(newest, prev), doctest::Contains(newest_damage.c_str()),
                       std::runtime_error);
}

namespace {

// The message config_from_json gives `settings` read from RUN/run.json, or "" when it accepts them.
std::string refusal(const nlohmann::json& settings) {
  try {
    run::config_from_json(settings, "RUN/run.json");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("settings from JSON are checked by type and range, each refusal as 'SOURCE: field KEY = VALUE: why'") {
  struct Case {
    const char* key;
    nlohmann::json value;
    const char* shown;
    const char* why;  // a part of the reason
  };
  const Case cases[] = {
      {"iterations", -5, "-5", "must not be negative"},  // the JSON library would make it 4294967291
      {"iterations", 0, "0", "must be at least 1"},
      {"iterations", 2.5, "2.5", "whole number"},
      {"iterations", "many", "\"many\"", "whole number"},
      {"iterations", 5e9, "5000000000.0", "must be in 0..4294967295"},
      {"fine_iterations", -1, "-1", "must not be negative"},
      {"sh_degree", 9, "9", "0..3"},
      {"budget", 0, "0", "at least 1"},
      {"fine_batch", 0, "0", "at least 1"},
      {"downscale", 0, "0", "at least 1"},
      {"means_lr", 0, "0", "a learning rate must be a finite number > 0"},
      {"grid_lr_final", -1e-4, "-1e-04", "a learning rate must be a finite number > 0"},
      {"lr_scale", 0, "0", "a learning rate must be a finite number > 0"},
      {"ssim_weight", 1e300, "1e+300", "outside the float range"},
      {"ssim_weight", 1.5, "1.5", "[0, 1]"},
      {"max_time", 1.5, "1.5", "[0, 1]"},
      {"static_max_time", 2, "2", "or negative to choose it from the data"},
      {"fine_time_front", -0.5, "-0.5", "[0, 1]"},
      {"background", {0, 2, 0}, "[0, 2, 0]", "each component must be in [0, 1]"},
      {"background", {1, 1}, "[1,1]", "an array of 3 numbers"},
      {"field_resolution", {2, 64, 64, 10}, "[2, 64, 64, 10]", "at least 3"},
      {"field_multires", nlohmann::json::array(), "[]", "1..4 levels"},
      {"field_multires", {1, 2, 3, 4, 5}, "[1, 2, 3, 4, 5]", "1..4 levels"},
      {"field_channels", 0, "0", "1..32"},
      {"field_channels", 64, "64", "1..32"},
      {"field_width", 256, "256", "1..128"},
      {"field_trunk_extra", 4, "4", "0..3"},
      {"field_heads", 0, "0", "head bits"},
      {"field_heads", 32, "32", "head bits"},
      {"densify_every", 0, "0", "interval"},
      {"opacity_reset_every", 0, "0", "interval"},
      {"test_every", 0, "0", "interval"},
      {"checkpoint_every", 0, "0", "interval"},
      {"max_screen_radius", 0, "0", "> 0"},
      {"static_motion", -1, "-1", ">= 0"},
      {"motion_samples", 1, "1", "at least 2"},
      {"plane_tv_weight", -1, "-1", ">= 0"},
      {"preset", 3, "3", "expected a string"},
  };
  for (const Case& c : cases) {
    const std::string key = c.key, value = c.value.dump();
    CAPTURE(key);
    CAPTURE(value);
    const std::string message = refusal({{c.key, c.value}});
    const std::string head = std::string("RUN/run.json: field '") + c.key + "' = " + c.shown + ": ";
    CHECK_MESSAGE(message.rfind(head, 0) == 0, message);
    CHECK_MESSAGE(message.find(c.why) != std::string::npos, message);
  }
  // What is allowed: no fine stage, the static stage's time left to the data, a count written as 1e4.
  CHECK(refusal({{"fine_iterations", 0}, {"static_max_time", -1}, {"iterations", 1e4}}).empty());
  CHECK(run::config_from_json({{"iterations", 1e4}}, "x").iterations == 10000);
  CHECK(refusal(nlohmann::json::array()) == "RUN/run.json: the training settings are a JSON array, expected a JSON object");
  CHECK(refusal("fast") == "RUN/run.json: the training settings are a JSON string, expected a JSON object");
  // Every preset passes, and so does what a run stores of it.
  for (const char* name : {"fast", "default", "quality"}) {
    CAPTURE(name);
    CHECK_NOTHROW(run::validate(run::preset_config(name), std::string("preset ") + name));
    CHECK(refusal(run::to_json(run::preset_config(name))).empty());
  }
}

TEST_CASE("validate refuses non-finite values held in memory, naming the source") {
  run::TrainConfig c = run::preset_config("fast");
  c.means_lr = NAN;
  CHECK_THROWS_WITH_AS(run::validate(c, "--set"), "--set: field 'means_lr' = nan: a learning rate must be a finite number > 0",
                       std::runtime_error);
  c = run::preset_config("fast");
  c.max_time = INFINITY;
  CHECK_THROWS_WITH_AS(run::validate(c, "command line"), "command line: field 'max_time' = inf: must be a time in [0, 1]",
                       std::runtime_error);
  c = run::preset_config("fast");
  c.background = {0.5f, NAN, 0};
  CHECK_THROWS_WITH_AS(run::validate(c, "x"), "x: field 'background' = [0.5, nan, 0]: each component must be in [0, 1]",
                       std::runtime_error);
}

TEST_CASE("the run lock admits one writer, lets shared holders coexist, and is gone when its holder dies") {
  const fs::path dir = fresh_dir("s4d_run_lock");
  // Takes the lock and lets it go at once.
  auto take = [](const fs::path& d, run::RunLock::Mode mode = run::RunLock::Mode::exclusive) { run::RunLock l(d, mode); };
  const std::string locked = dir.string() + ": locked by another style4d process (pid ";
  const std::string me = locked + std::to_string(::getpid()) + ")";
  {
    run::RunLock held(dir);
    CHECK(read_bytes(dir / ".lock") == std::to_string(::getpid()) + "\n");
    // A second open of the file conflicts, in this process too (flock locks belong to open files).
    CHECK_THROWS_WITH_AS(take(dir), me.c_str(), run::RunLocked);
    CHECK_THROWS_WITH_AS(take(dir, run::RunLock::Mode::shared), me.c_str(), run::RunLocked);
    CHECK(run::empty_but_for_lock(dir));
  }
  {
    run::RunLock a(dir, run::RunLock::Mode::shared), b(dir, run::RunLock::Mode::shared);
    CHECK_THROWS_WITH_AS(take(dir), me.c_str(), run::RunLocked);
    a.release();
    CHECK_THROWS_AS(take(dir), run::RunLocked);  // b still holds it
  }
  run::RunLock again(dir);
  again.release(/*remove_file=*/true);
  CHECK_FALSE(fs::exists(dir / ".lock"));
  CHECK_NOTHROW(take(dir));
  CHECK_THROWS_AS(take(dir / "missing"), std::runtime_error);

  // Held by another process that is then killed with SIGKILL: refused with its pid, then free at once.
  int ready[2];
  REQUIRE(::pipe(ready) == 0);
  const std::string file = (dir / ".lock").string();
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // only async-signal-safe calls after fork
    const int fd = ::open(file.c_str(), O_RDWR | O_CREAT, 0644);
    const char ok = (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0) ? '1' : '0';
    if (::write(ready[1], &ok, 1) != 1) ::_exit(2);
    while (true) ::pause();
  }
  char ok = 0;
  REQUIRE(::read(ready[0], &ok, 1) == 1);
  ::close(ready[0]);
  ::close(ready[1]);
  CHECK(ok == '1');
  CHECK_THROWS_WITH_AS(take(dir), (locked + std::to_string(child) + ")").c_str(), run::RunLocked);
  ::kill(child, SIGKILL);
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  CHECK_NOTHROW(take(dir));
}
