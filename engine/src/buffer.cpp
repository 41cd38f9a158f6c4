#include "s4d/engine/buffer.h"

#include <stdexcept>
#include <utility>

#include "s4d/engine/check.h"
#include "s4d/engine/context.h"

namespace s4d::engine {

namespace {
std::string mib(uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }
}  // namespace

Buffer::Buffer(Context& ctx, std::string name, size_t bytes, BufferKind kind)
    : ctx_(&ctx), name_(std::move(name)), size_(bytes), kind_(kind) {
  const DeviceInfo& info = ctx.info();
  if (kind == BufferKind::storage && bytes > info.max_storage_buffer_range)
    throw std::invalid_argument("buffer '" + name_ + "' needs " + std::to_string(bytes) + " bytes (" + mib(bytes) +
                                ") but " + info.name + " allows at most " + std::to_string(info.max_storage_buffer_range) +
                                " bytes (" + mib(info.max_storage_buffer_range) + ", maxStorageBufferRange) per storage buffer");
  if (bytes > info.max_memory_allocation_size)
    throw std::invalid_argument("buffer '" + name_ + "' needs " + std::to_string(bytes) + " bytes but " + info.name +
                                " allows at most " + std::to_string(info.max_memory_allocation_size) +
                                " bytes per allocation (maxMemoryAllocationSize)");
  // Vulkan forbids empty buffers; an empty Buffer still gets a small allocation so it can be bound.
  const VkDeviceSize alloc_bytes = bytes == 0 ? 16 : bytes;
  const VkBufferUsageFlags usage =
      kind == BufferKind::storage
          ? VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT  // kernels may write dispatch arguments (Recorder::dispatch_indirect)
          : VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBufferCreateInfo bci{.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                         .size = alloc_bytes,
                         .usage = usage,
                         .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
  S4D_VK_CHECK_CTX(vkCreateBuffer(ctx.device(), &bci, nullptr, &buffer_), "creating buffer '" + name_ + "'");

  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
    VkMemoryPropertyFlags required, preferred;
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (kind == BufferKind::staging) {
      required = host;
      preferred = host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
    } else if (ctx.unified_memory()) {
      // CPU and UMA devices: device-local memory is host memory, so map it and skip staging copies.
      required = host;
      preferred = host | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    } else {
      required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    }
    VkMemoryAllocateInfo mai{.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                             .allocationSize = req.size,
                             .memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, required, preferred)};
    S4D_VK_CHECK_CTX(vkAllocateMemory(ctx.device(), &mai, nullptr, &memory_),
                     "allocating " + std::to_string(req.size) + " bytes for buffer '" + name_ + "' on " + info.name);
    memory_bytes_ = req.size;
    ctx.count_memory(static_cast<int64_t>(memory_bytes_));
    S4D_VK_CHECK_CTX(vkBindBufferMemory(ctx.device(), buffer_, memory_, 0), "binding memory of buffer '" + name_ + "'");
    if ((required & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0)
      S4D_VK_CHECK_CTX(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "mapping buffer '" + name_ + "'");
    ctx.set_name(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(buffer_), name_);
    ctx.set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, reinterpret_cast<uint64_t>(memory_), name_ + " memory");
  } catch (...) {
    release();  // the destructor does not run for a constructor that threw
    throw;
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept
    : ctx_(other.ctx_),
      name_(std::move(other.name_)),
      size_(other.size_),
      kind_(other.kind_),
      buffer_(std::exchange(other.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(other.memory_, VK_NULL_HANDLE)),
      memory_bytes_(std::exchange(other.memory_bytes_, 0)),
      mapped_(std::exchange(other.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    ctx_ = other.ctx_;
    name_ = std::move(other.name_);
    size_ = other.size_;
    kind_ = other.kind_;
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    memory_bytes_ = std::exchange(other.memory_bytes_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::release() {
  if (!ctx_ || (buffer_ == VK_NULL_HANDLE && memory_ == VK_NULL_HANDLE)) return;
  VkDevice device = ctx_->device();
  VkBuffer buffer = std::exchange(buffer_, VK_NULL_HANDLE);
  VkDeviceMemory memory = std::exchange(memory_, VK_NULL_HANDLE);
  mapped_ = nullptr;
  ctx_->count_memory(-static_cast<int64_t>(std::exchange(memory_bytes_, 0)));
  ctx_->retire([device, buffer, memory] {
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);  // also unmaps
  });
}

}  // namespace s4d::engine
