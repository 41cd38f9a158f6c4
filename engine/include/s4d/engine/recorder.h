// Records compute work into one command buffer; the context submits it. Every dispatch goes
// through dispatch(), which checks the buffers and push constants against the pipeline's reflected
// layout and splits group counts past the device limit into a 2-D grid (kernels recover the flat
// group index with flat_group_id() from shaders/include/flat_group.glsl).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <type_traits>

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

  // Dispatches `flat_groups` workgroups of `pipeline`; 0 records nothing. `buffers` bind to
  // bindings 0..n-1 of set 0 in order and must match the pipeline's binding count exactly;
  // `params` must match its push-constant size exactly. Throws std::invalid_argument otherwise.
  template <class Params>
  void dispatch(const Pipeline& pipeline, std::initializer_list<BufferRange> buffers, const Params& params,
                uint32_t flat_groups) {
    static_assert(std::is_trivially_copyable_v<Params>);
    dispatch_raw(pipeline, std::span(buffers.begin(), buffers.size()), &params, sizeof(Params), flat_groups);
  }
  void dispatch_raw(const Pipeline& pipeline, std::span<const BufferRange> buffers, const void* params,
                    size_t params_bytes, uint32_t flat_groups);

  // The grid a flat group count is split into under the device's limits.
  Groups split_groups(uint32_t flat_groups) const;

  // Full compute/transfer -> compute/transfer memory barrier between dependent commands.
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
  Context* ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  bool finished_ = false;
};

}  // namespace s4d::engine
