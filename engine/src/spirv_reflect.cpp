#include "s4d/engine/spirv_reflect.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace s4d::engine {

namespace {

// Opcodes and enumerants from the SPIR-V specification (unified1).
constexpr uint32_t kMagic = 0x07230203;
enum Op : uint32_t {
  OpName = 5,
  OpMemberName = 6,
  OpExecutionMode = 16,
  OpTypeInt = 21,
  OpTypeFloat = 22,
  OpTypeVector = 23,
  OpTypeMatrix = 24,
  OpTypeArray = 28,
  OpTypeRuntimeArray = 29,
  OpTypeStruct = 30,
  OpTypePointer = 32,
  OpConstant = 43,
  OpVariable = 59,
  OpDecorate = 71,
  OpMemberDecorate = 72,
};
constexpr uint32_t kExecutionModeLocalSize = 17;
constexpr uint32_t kDecorationArrayStride = 6;
constexpr uint32_t kDecorationMatrixStride = 7;
constexpr uint32_t kDecorationBinding = 33;
constexpr uint32_t kDecorationDescriptorSet = 34;
constexpr uint32_t kDecorationOffset = 35;
constexpr uint32_t kStorageUniform = 2;
constexpr uint32_t kStoragePushConstant = 9;
constexpr uint32_t kStorageStorageBuffer = 12;

std::string read_string(std::span<const uint32_t> words) {
  std::string s;
  for (uint32_t w : words) {
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((w >> (8 * b)) & 0xffu);
      if (c == 0) return s;
      s.push_back(c);
    }
  }
  return s;
}

struct Type {
  uint32_t op = 0;
  std::vector<uint32_t> operands;  // words after the result id
};

class Walker {
 public:
  Walker(std::span<const uint32_t> words, const std::string& name) : words_(words), name_(name) {}

  ModuleReflection run() {
    if (words_.size() < 5 || words_[0] != kMagic) fail("not a SPIR-V module (bad magic or too short)");
    size_t pos = 5;
    while (pos < words_.size()) {
      const uint32_t count = words_[pos] >> 16;
      const uint32_t op = words_[pos] & 0xffffu;
      if (count == 0 || pos + count > words_.size()) fail("truncated instruction at word " + std::to_string(pos));
      visit(op, words_.subspan(pos + 1, count - 1));
      pos += count;
    }
    return finish();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("SPIR-V module '" + name_ + "': " + what);
  }

  void visit(uint32_t op, std::span<const uint32_t> a) {
    auto need = [&](size_t n) {
      if (a.size() < n) fail("instruction with opcode " + std::to_string(op) + " has too few operands");
    };
    switch (op) {
      case OpName:
        need(2);
        names_[a[0]] = read_string(a.subspan(1));
        break;
      case OpMemberName:
        need(3);
        member_names_[a[0]][a[1]] = read_string(a.subspan(2));
        break;
      case OpExecutionMode:
        need(2);
        if (a[1] == kExecutionModeLocalSize) {
          need(5);
          for (int i = 0; i < 3; ++i) out_.local_size[i] = a[2 + i];
        }
        break;
      case OpTypeInt:
      case OpTypeFloat:
      case OpTypeVector:
      case OpTypeMatrix:
      case OpTypeArray:
      case OpTypeRuntimeArray:
      case OpTypeStruct:
      case OpTypePointer:
        need(1);
        types_[a[0]] = Type{op, std::vector<uint32_t>(a.begin() + 1, a.end())};
        break;
      case OpConstant:
        need(3);
        constants_[a[1]] = a[2];  // low word is enough for array lengths
        break;
      case OpVariable:
        need(3);
        variables_.push_back({a[1], a[0], a[2]});
        break;
      case OpDecorate:
        need(2);
        if (a[1] == kDecorationBinding && a.size() >= 3) binding_[a[0]] = a[2];
        if (a[1] == kDecorationDescriptorSet && a.size() >= 3) set_[a[0]] = a[2];
        if (a[1] == kDecorationArrayStride && a.size() >= 3) array_stride_[a[0]] = a[2];
        break;
      case OpMemberDecorate:
        need(3);
        if (a[2] == kDecorationOffset && a.size() >= 4) offsets_[a[0]][a[1]] = a[3];
        if (a[2] == kDecorationMatrixStride && a.size() >= 4) matrix_stride_[a[0]][a[1]] = a[3];
        break;
      default:
        break;
    }
  }

  const Type& type(uint32_t id) const {
    auto it = types_.find(id);
    if (it == types_.end()) fail("reference to unknown type id " + std::to_string(id));
    return it->second;
  }

  // Byte size of a type as laid out in an explicitly-offset block (runtime arrays count 0).
  uint32_t size_of(uint32_t id, uint32_t matrix_stride = 0) const {
    const Type& t = type(id);
    switch (t.op) {
      case OpTypeInt:
      case OpTypeFloat:
        return t.operands.at(0) / 8;
      case OpTypeVector:
        return size_of(t.operands.at(0)) * t.operands.at(1);
      case OpTypeMatrix:
        return (matrix_stride ? matrix_stride : size_of(t.operands.at(0))) * t.operands.at(1);
      case OpTypeArray: {
        auto stride = array_stride_.find(id);
        auto len = constants_.find(t.operands.at(1));
        if (len == constants_.end()) fail("array length of type " + std::to_string(id) + " is not a plain constant");
        const uint32_t elem = stride != array_stride_.end() ? stride->second : size_of(t.operands.at(0));
        return elem * len->second;
      }
      case OpTypeRuntimeArray:
        return 0;
      case OpTypeStruct:
        return struct_layout(id).extent;
      default:
        fail("type id " + std::to_string(id) + " has no size");
    }
  }

  StructLayout struct_layout(uint32_t id) const {
    const Type& t = type(id);
    StructLayout s;
    auto nm = names_.find(id);
    s.name = nm != names_.end() ? nm->second : "";
    auto offs = offsets_.find(id);
    auto mnames = member_names_.find(id);
    auto mstrides = matrix_stride_.find(id);
    for (uint32_t m = 0; m < t.operands.size(); ++m) {
      StructMember member;
      if (mnames != member_names_.end() && mnames->second.count(m)) member.name = mnames->second.at(m);
      if (offs == offsets_.end() || !offs->second.count(m))
        fail("struct '" + s.name + "' member " + std::to_string(m) + " has no Offset decoration");
      member.offset = offs->second.at(m);
      uint32_t mstride = 0;
      if (mstrides != matrix_stride_.end() && mstrides->second.count(m)) mstride = mstrides->second.at(m);
      member.size = size_of(t.operands[m], mstride);
      s.extent = std::max(s.extent, member.offset + member.size);
      s.members.push_back(member);
    }
    return s;
  }

  ModuleReflection finish() {
    for (const auto& [id, t] : types_) {
      if (t.op != OpTypeStruct || !offsets_.count(id)) continue;  // only explicitly laid-out structs
      StructLayout s = struct_layout(id);
      if (!s.name.empty()) out_.structs.emplace(s.name, std::move(s));
    }
    std::set<std::pair<uint32_t, uint32_t>> seen;
    for (const Variable& v : variables_) {
      const Type& ptr = type(v.type);
      if (ptr.op != OpTypePointer) continue;
      const uint32_t pointee = ptr.operands.at(1);
      if (v.storage == kStoragePushConstant) {
        out_.push_constant_bytes = size_of(pointee);
      } else if (v.storage == kStorageStorageBuffer || v.storage == kStorageUniform) {
        if (!binding_.count(v.id)) fail("buffer variable " + std::to_string(v.id) + " has no Binding decoration");
        auto block = names_.find(pointee);
        DescriptorBinding b{set_.count(v.id) ? set_.at(v.id) : 0, binding_.at(v.id), v.storage == kStorageStorageBuffer,
                            block != names_.end() ? block->second : ""};
        if (!seen.insert({b.set, b.binding}).second)
          fail("two variables share set " + std::to_string(b.set) + " binding " + std::to_string(b.binding));
        out_.bindings.push_back(b);
      }
    }
    std::sort(out_.bindings.begin(), out_.bindings.end(), [](const auto& x, const auto& y) {
      return std::pair(x.set, x.binding) < std::pair(y.set, y.binding);
    });
    return out_;
  }

  struct Variable {
    uint32_t id, type, storage;
  };
  std::span<const uint32_t> words_;
  std::string name_;
  ModuleReflection out_;
  std::unordered_map<uint32_t, std::string> names_;
  std::unordered_map<uint32_t, std::map<uint32_t, std::string>> member_names_;
  std::unordered_map<uint32_t, Type> types_;
  std::unordered_map<uint32_t, uint32_t> constants_;
  std::vector<Variable> variables_;
  std::unordered_map<uint32_t, uint32_t> binding_, set_, array_stride_;
  std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> offsets_, matrix_stride_;
};

}  // namespace

ModuleReflection reflect_spirv(std::span<const uint32_t> words, const std::string& module_name) {
  return Walker(words, module_name).run();
}

std::vector<std::string> compare_layouts(const CppStructLayout& cpp, const StructLayout& spirv) {
  std::vector<std::string> diffs;
  const std::string who = "struct " + cpp.name + ": ";
  if (cpp.members.size() != spirv.members.size())
    diffs.push_back(who + "C++ has " + std::to_string(cpp.members.size()) + " members, SPIR-V has " +
                    std::to_string(spirv.members.size()));
  const size_t n = std::min(cpp.members.size(), spirv.members.size());
  for (size_t i = 0; i < n; ++i) {
    const StructMember& c = cpp.members[i];
    const StructMember& s = spirv.members[i];
    if (c.name != s.name) diffs.push_back(who + "member " + std::to_string(i) + " is '" + c.name + "' in C++ but '" + s.name + "' in SPIR-V");
    if (c.offset != s.offset)
      diffs.push_back(who + "member '" + c.name + "' at offset " + std::to_string(c.offset) + " in C++ but " + std::to_string(s.offset) + " in SPIR-V");
    if (c.size != s.size)
      diffs.push_back(who + "member '" + c.name + "' is " + std::to_string(c.size) + " bytes in C++ but " + std::to_string(s.size) + " in SPIR-V");
  }
  if (cpp.size != spirv.extent)
    diffs.push_back(who + "sizeof is " + std::to_string(cpp.size) + " in C++ but the SPIR-V extent is " +
                    std::to_string(spirv.extent) + " (pad the struct explicitly)");
  return diffs;
}

}  // namespace s4d::engine
