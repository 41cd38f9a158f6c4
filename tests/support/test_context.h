// The one Vulkan context a test process shares (created on first use), with validation on unless
// S4D_VALIDATION=0. Any validation error during a test case fails the run: the listener in
// test_main.cpp reports it against the test case and the process exits non-zero.
#pragma once
#include "s4d/engine/context.h"

namespace s4d::test {

engine::Context& context();
bool context_created();
// Destroys the shared context (main does, before returning: a Vulkan device torn down by static
// destructors after the driver's own can crash the process at exit, as NVIDIA's 580 driver did).
void release_context();

}  // namespace s4d::test
