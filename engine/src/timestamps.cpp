#include "s4d/engine/timestamps.h"

#include <stdexcept>

#include "s4d/engine/check.h"
#include "s4d/engine/context.h"

namespace s4d::engine {

TimestampQueries::TimestampQueries(Context& ctx, uint32_t count, const std::string& name) : ctx_(ctx), count_(count) {
  if (!ctx.info().timestamps)
    throw std::runtime_error("GPU timestamps are not supported on the compute queue of " + ctx.info().name);
  VkQueryPoolCreateInfo ci{.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                           .queryType = VK_QUERY_TYPE_TIMESTAMP,
                           .queryCount = count};
  S4D_VK_CHECK_CTX(vkCreateQueryPool(ctx.device(), &ci, nullptr, &pool_), "creating query pool '" + name + "'");
  ctx.set_name(VK_OBJECT_TYPE_QUERY_POOL, reinterpret_cast<uint64_t>(pool_), name);
}

TimestampQueries::~TimestampQueries() {
  VkDevice device = ctx_.device();
  VkQueryPool pool = pool_;
  ctx_.retire([device, pool] { vkDestroyQueryPool(device, pool, nullptr); });
}

double TimestampQueries::elapsed_ms(uint32_t from, uint32_t to) const { return ticks_ms(ticks(from), ticks(to)); }

uint64_t TimestampQueries::ticks(uint32_t index) const {
  if (index >= count_) throw std::out_of_range("timestamp query index past the pool's " + std::to_string(count_));
  uint64_t t = 0;
  S4D_VK_CHECK(vkGetQueryPoolResults(ctx_.device(), pool_, index, 1, sizeof(uint64_t), &t, sizeof(uint64_t),
                                     VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  return t;
}

double TimestampQueries::ticks_ms(uint64_t from, uint64_t to) const {
  // Masked: the counter may wrap between the two queries.
  const uint32_t bits = ctx_.info().timestamp_valid_bits;
  const uint64_t mask = bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
  return static_cast<double>((to - from) & mask) * static_cast<double>(ctx_.info().timestamp_period_ns) * 1e-6;
}

}  // namespace s4d::engine
