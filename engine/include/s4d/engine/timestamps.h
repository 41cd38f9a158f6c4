// GPU timestamps: a query pool the recorder writes into; read after the submission completes.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace s4d::engine {

class Context;

class TimestampQueries {
 public:
  // Throws std::runtime_error when the device's compute queue has no timestamp support.
  TimestampQueries(Context& ctx, uint32_t count, const std::string& name);
  ~TimestampQueries();
  TimestampQueries(const TimestampQueries&) = delete;
  TimestampQueries& operator=(const TimestampQueries&) = delete;

  VkQueryPool handle() const { return pool_; }
  uint32_t count() const { return count_; }
  // Milliseconds between query `from` and query `to`; waits for both results.
  double elapsed_ms(uint32_t from, uint32_t to) const;
  // The device's counter at query `index`; waits for the result.
  uint64_t ticks(uint32_t index) const;
  // Milliseconds from counter value `from` to `to` (of any pool of the same device).
  double ticks_ms(uint64_t from, uint64_t to) const;

 private:
  Context& ctx_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t count_ = 0;
};

}  // namespace s4d::engine
