#include "test_context.h"

#include <cstdlib>
#include <memory>

namespace s4d::test {

namespace {
std::unique_ptr<engine::Context>& slot() {
  static std::unique_ptr<engine::Context> ctx;
  return ctx;
}
}  // namespace

engine::Context& context() {
  auto& ctx = slot();
  if (!ctx) {
    engine::ContextOptions options = engine::ContextOptions::from_env();
    const char* v = std::getenv("S4D_VALIDATION");
    options.validation = !(v && std::string(v) == "0");
    ctx = std::make_unique<engine::Context>(options);
  }
  return *ctx;
}

bool context_created() { return slot() != nullptr; }

void release_context() { slot().reset(); }

}  // namespace s4d::test
