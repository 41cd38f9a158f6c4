// A small SPIR-V word walker: what the engine needs to build a pipeline from a module (workgroup
// size, descriptor bindings and their block names, push-constant size) and what the layout tests need to compare shared
// GLSL/C++ structs (member names and offsets of every named struct type).
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace s4d::engine {

struct StructMember {
  std::string name;
  uint32_t offset = 0;  // OpMemberDecorate ... Offset
  uint32_t size = 0;    // byte size of the member type (0 for a runtime array)
};

struct StructLayout {
  std::string name;  // OpName of the struct type
  std::vector<StructMember> members;
  uint32_t extent = 0;  // max(offset + size) over members: the std430/std140 byte size without tail padding
};

struct DescriptorBinding {
  uint32_t set = 0;
  uint32_t binding = 0;
  bool storage_buffer = true;  // false: uniform buffer
  std::string block;           // OpName of the buffer's block type ("" when the module has no names)
};

struct ModuleReflection {
  uint32_t local_size[3] = {1, 1, 1};
  std::vector<DescriptorBinding> bindings;  // sorted by (set, binding)
  uint32_t push_constant_bytes = 0;         // extent of the push-constant block, 0 if none
  std::multimap<std::string, StructLayout> structs;  // every named struct type with explicit offsets
};

// Parses a SPIR-V module. Throws std::invalid_argument (naming `module_name`) on a malformed module.
ModuleReflection reflect_spirv(std::span<const uint32_t> words, const std::string& module_name);

// Expected layout of a C++ struct, for comparison with the SPIR-V (built with offsetof/sizeof).
struct CppStructLayout {
  std::string name;
  uint32_t size = 0;  // sizeof
  std::vector<StructMember> members;
};

// Differences between a C++ struct and its SPIR-V counterpart: member count, names, offsets,
// sizes, and sizeof vs the SPIR-V extent (shared structs are padded explicitly, so they must be
// equal). Empty when they agree.
std::vector<std::string> compare_layouts(const CppStructLayout& cpp, const StructLayout& spirv);

}  // namespace s4d::engine
