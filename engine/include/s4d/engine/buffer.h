// A device buffer: move-only, named, destroyed through the context's retire list once no
// submission can still use it.
#pragma once
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace s4d::engine {

class Context;

enum class BufferKind {
  storage,  // shader-visible storage buffer (size limited by maxStorageBufferRange)
  staging,  // host-visible transfer source/destination
};

class Buffer {
 public:
  Buffer() = default;
  // Throws std::invalid_argument naming the buffer when `bytes` exceeds the device's storage-buffer
  // range or allocation limit, and VulkanError naming it when memory runs out.
  Buffer(Context& ctx, std::string name, size_t bytes, BufferKind kind = BufferKind::storage);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  size_t size() const { return size_; }
  const std::string& name() const { return name_; }
  bool valid() const { return buffer_ != VK_NULL_HANDLE; }
  BufferKind kind() const { return kind_; }
  // Persistent host mapping when the memory is host-visible, else nullptr.
  void* mapped() const { return mapped_; }

 private:
  void release();

  Context* ctx_ = nullptr;
  std::string name_;
  size_t size_ = 0;
  BufferKind kind_ = BufferKind::storage;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  uint64_t memory_bytes_ = 0;  // what memory_ holds, counted in the context's memory use
  void* mapped_ = nullptr;
};

}  // namespace s4d::engine
