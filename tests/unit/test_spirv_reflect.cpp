// The SPIR-V walker: reflection of real embedded modules (block names included), and proof that
// the layout comparison catches each kind of mismatch it is meant to catch.
#include <doctest/doctest.h>

#include <stdexcept>
#include <vector>

#include "s4d/engine/spirv_reflect.h"
#include "s4d/shader_registry.h"
#include "s4d_primitives.h"

using namespace s4d::engine;

namespace {

ModuleReflection reflect(s4d::shaders::Id id) {
  const auto& e = s4d::shaders::get(id);
  return reflect_spirv(e.spirv(), e.name);
}

StructLayout scan_params_in_spirv() {
  const auto m = reflect(s4d::shaders::Id::scan_downsweep);
  auto it = m.structs.find("ScanParams");
  REQUIRE(it != m.structs.end());
  return it->second;
}

CppStructLayout correct_scan_params() {
  return {"ScanParams", 16, {{"n", 0, 4}, {"num_blocks", 4, 4}, {"_pad0", 8, 4}, {"_pad1", 12, 4}}};
}

bool mentions(const std::vector<std::string>& diffs, const std::string& text) {
  for (const auto& d : diffs)
    if (d.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("reflection reads workgroup size, bindings and push-constant size") {
  const auto iota = reflect(s4d::shaders::Id::iota);
  CHECK(iota.local_size[0] == S4D_IOTA_WG);
  CHECK(iota.local_size[1] == 1);
  CHECK(iota.bindings.size() == 1);
  CHECK(iota.push_constant_bytes == sizeof(s4d::gpu::IotaParams));

  const auto scatter = reflect(s4d::shaders::Id::radix_scatter);
  REQUIRE(scatter.bindings.size() == 5);
  const char* blocks[] = {"KeysIn", "ValuesIn", "Hist", "KeysOut", "ValuesOut"};
  for (uint32_t i = 0; i < 5; ++i) {
    CHECK(scatter.bindings[i].binding == i);
    CHECK(scatter.bindings[i].storage_buffer);
    CHECK(scatter.bindings[i].block == blocks[i]);
  }
}

TEST_CASE("every buffer block of every shader keeps its name, which dispatch checks binding ids against") {
  for (const auto& entry : s4d::shaders::all())
    for (const DescriptorBinding& b : reflect_spirv(entry.spirv(), entry.name).bindings)
      CHECK_MESSAGE(!b.block.empty(), entry.name << " binding " << b.binding << " has no block name");
}

TEST_CASE("layout comparison accepts the real layout") {
  CHECK(compare_layouts(correct_scan_params(), scan_params_in_spirv()).empty());
}

TEST_CASE("layout comparison catches a wrong offset, name, size, member count and missing padding") {
  const StructLayout spirv = scan_params_in_spirv();

  CppStructLayout wrong_offset = correct_scan_params();
  wrong_offset.members[1].offset = 8;
  CHECK(mentions(compare_layouts(wrong_offset, spirv), "member 'num_blocks' at offset 8 in C++ but 4 in SPIR-V"));

  CppStructLayout wrong_name = correct_scan_params();
  wrong_name.members[0].name = "count";
  CHECK(mentions(compare_layouts(wrong_name, spirv), "'count' in C++ but 'n' in SPIR-V"));

  CppStructLayout wrong_size = correct_scan_params();
  wrong_size.members[0].size = 8;
  CHECK(mentions(compare_layouts(wrong_size, spirv), "is 8 bytes in C++ but 4 in SPIR-V"));

  CppStructLayout missing_member = correct_scan_params();
  missing_member.members.pop_back();
  CHECK(mentions(compare_layouts(missing_member, spirv), "C++ has 3 members, SPIR-V has 4"));

  CppStructLayout tail_padding = correct_scan_params();
  tail_padding.size = 32;
  CHECK(mentions(compare_layouts(tail_padding, spirv), "sizeof is 32 in C++ but the SPIR-V extent is 16"));
}

TEST_CASE("malformed SPIR-V is rejected with the module's name") {
  const std::vector<uint32_t> bad_magic = {0xdeadbeef, 0, 0, 0, 0};
  CHECK_THROWS_WITH_AS(reflect_spirv(bad_magic, "broken.spv"), doctest::Contains("broken.spv"), std::invalid_argument);

  const auto& e = s4d::shaders::get(s4d::shaders::Id::iota);
  std::vector<uint32_t> truncated(e.words, e.words + e.word_count);
  truncated.resize(6);  // header + the first word of a two-word OpCapability
  CHECK_THROWS_WITH_AS(reflect_spirv(truncated, "cut.spv"), doctest::Contains("truncated"), std::invalid_argument);
}
