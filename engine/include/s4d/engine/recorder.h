// Records compute work into one command buffer; the context submits it. Every dispatch goes
// through dispatch(), which binds buffers by their S4D_B_* ids, checks them and the push constants
// against the pipeline's reflected layout and splits group counts past the device limit into a 2-D
// grid (kernels recover the flat group index with flat_group_id() from shaders/include/flat_group.glsl).
// With a stage timer installed on the context (stage_timer.h), every command first lets it write a
// timestamp where the stage changes.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "s4d/engine/stage_timer.h"

namespace s4d::engine {

class Buffer;
class Context;
class Pipeline;
class TimestampQueries;

// A buffer, or a byte range of one, bound to a descriptor.
struct BufferRange {
  const Buffer* buffer = nullptr;
  size_t offset = 0;
  size_t bytes = 0;  // 0: to the end of the buffer
  BufferRange(const Buffer& b, size_t offset_bytes = 0, size_t size_bytes = 0)  // NOLINT: implicit by design
      : buffer(&b), offset(offset_bytes), bytes(size_bytes) {}
};

// A buffer bound to a binding id of a kernel's shared header, with the id's name for messages
// and for the check against the shader's block name. Write it with S4D_BIND.
struct Binding {
  uint32_t id;
  const char* name;  // "S4D_B_ADAM_PARAMS"
  BufferRange range;
};

// S4D_BIND(ADAM_PARAMS, params) binds `params` to S4D_B_ADAM_PARAMS; S4D_BIND(SCAN_DATA, buffer,
// offset, bytes) binds a range. An id that no included shared header defines fails to compile.
#define S4D_BIND(ID, ...) \
  ::s4d::engine::Binding { S4D_B_##ID, "S4D_B_" #ID, ::s4d::engine::BufferRange(__VA_ARGS__) }

// Whether an id's name agrees with the shader's block at that binding: the block's name less a
// first and a last word In or Out (words start at upper-case letters), in lower case, is part of
// the id's name less S4D_B_ and underscores (S4D_B_ADAM_PARAMS: block Params; S4D_B_RASTER_RGB:
// block OutRgb). An id of another kernel's header fails it. A block without a name (a module
// stripped of names) agrees with any id.
bool binding_name_agrees(std::string_view id_name, std::string_view block);

struct Groups {
  uint32_t x = 1, y = 1, z = 1;
};

class Recorder {
 public:
  explicit Recorder(Context& ctx, const std::string& name = "commands");
  ~Recorder();
  Recorder(Recorder&& other) noexcept;
  Recorder& operator=(Recorder&&) = delete;
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Dispatches `flat_groups` workgroups of `pipeline`; 0 records nothing. `bindings` come in any
  // order and must bind each binding of the shader exactly once, each by an id whose name agrees
  // with the shader's block there (binding_name_agrees). `params` must match the push-constant
  // size exactly. Throws std::invalid_argument naming the pipeline and the binding otherwise.
  template <class Params>
  void dispatch(const Pipeline& pipeline, std::initializer_list<Binding> bindings, const Params& params,
                uint32_t flat_groups) {
    static_assert(std::is_trivially_copyable_v<Params>);
    dispatch_raw(pipeline, std::span(bindings.begin(), bindings.size()), &params, sizeof(Params), flat_groups);
  }
  void dispatch_raw(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params,
                    size_t params_bytes, uint32_t flat_groups);

  // Same checks as dispatch(), with the group counts read on the device from `args` at `offset`
  // (VkDispatchIndirectCommand: three u32 x, y, z, each within the device's limits; a kernel that
  // writes them splits large counts into 2-D as split_groups() does). A barrier() must separate
  // the kernel that wrote them from this call.
  template <class Params>
  void dispatch_indirect(const Pipeline& pipeline, std::initializer_list<Binding> bindings, const Params& params,
                         const Buffer& args, size_t offset) {
    static_assert(std::is_trivially_copyable_v<Params>);
    dispatch_indirect_raw(pipeline, std::span(bindings.begin(), bindings.size()), &params, sizeof(Params), args,
                          offset);
  }
  void dispatch_indirect_raw(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params,
                             size_t params_bytes, const Buffer& args, size_t offset);

  // The grid a flat group count is split into under the device's limits.
  Groups split_groups(uint32_t flat_groups) const;

  // Full compute/transfer -> compute/transfer/indirect-argument memory barrier between dependent commands.
  void barrier();
  void copy(const Buffer& src, const Buffer& dst, size_t bytes, size_t src_offset = 0, size_t dst_offset = 0);
  void fill(const Buffer& dst, uint32_t value, size_t bytes = 0, size_t offset = 0);  // bytes 0: whole buffer
  void reset_queries(TimestampQueries& queries);
  void timestamp(TimestampQueries& queries, uint32_t index);
  void begin_label(const std::string& label);
  void end_label();

  Context& context() const { return *ctx_; }
  VkCommandBuffer handle() const { return cmd_; }
  // Ends recording and hands the command buffer to the caller (the context on submit).
  VkCommandBuffer finish();

 private:
  friend class Context;
  // Before each command: a timestamp where the stage timer's stage changes (nothing without a timer).
  void mark_stage();
  // dispatch_raw's checks; binds the pipeline, its descriptors and push constants.
  void bind(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params, size_t params_bytes);

  Context* ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  bool finished_ = false;
  StageMarks marks_;
};

}  // namespace s4d::engine
