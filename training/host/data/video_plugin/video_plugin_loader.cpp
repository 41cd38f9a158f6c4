// Opens the video plugin on the first video the program touches (video_plugin.h).
#include <dlfcn.h>

#include <stdexcept>
#include <string>

#include "video_plugin.h"

namespace s4d::data::video_plugin {

namespace {

// The table, or why there is none (kept, so that every later video names the same reason).
struct Loaded {
  const Api* api = nullptr;
  std::string error;
};

Loaded load() {
  // By name, so the program's RUNPATH finds it: next to style4d in a build, in lib/ in the release.
  // Never closed: the objects it returns have their code in it.
  void* handle = dlopen(kLibraryName, RTLD_NOW | RTLD_LOCAL);
  if (!handle) return {nullptr, std::string("the video plugin did not load: ") + dlerror()};
  auto entry = reinterpret_cast<const Api* (*)()>(dlsym(handle, kEntryPoint));
  if (!entry) return {nullptr, std::string(kLibraryName) + " has no " + kEntryPoint + " (not style4d's video plugin)"};
  const Api* table = entry();
  if (table->abi_version != kAbiVersion) {
    return {nullptr, std::string(kLibraryName) + " is from another build of style4d (interface " +
                         std::to_string(table->abi_version) + ", expected " + std::to_string(kAbiVersion) + ")"};
  }
  return {table, ""};
}

}  // namespace

const Api& api(const char* for_path) {
  static const Loaded loaded = load();
  if (!loaded.api) throw std::runtime_error(std::string(for_path) + ": cannot read or write videos: " + loaded.error);
  return *loaded.api;
}

}  // namespace s4d::data::video_plugin
