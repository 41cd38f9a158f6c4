#include "s4d/engine/recorder.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/check.h"
#include "s4d/engine/context.h"
#include "s4d/engine/pipeline.h"
#include "s4d/engine/timestamps.h"

namespace s4d::engine {

Recorder::Recorder(Context& ctx, const std::string& name) : ctx_(&ctx) {
  VkCommandBufferAllocateInfo ai{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                 .commandPool = ctx.command_pool(),
                                 .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                 .commandBufferCount = 1};
  S4D_VK_CHECK_CTX(vkAllocateCommandBuffers(ctx.device(), &ai, &cmd_), "allocating command buffer '" + name + "'");
  ctx.set_name(VK_OBJECT_TYPE_COMMAND_BUFFER, reinterpret_cast<uint64_t>(cmd_), name);
  VkCommandBufferBeginInfo bi{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                              .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  S4D_VK_CHECK(vkBeginCommandBuffer(cmd_, &bi));
  ctx.recorder_opened();
  // Writes of earlier submissions (kernels, copies) are only guaranteed visible to this command
  // buffer's reads through a memory dependency; a timeline wait alone does not give one.
  barrier();
}

Recorder::Recorder(Recorder&& other) noexcept
    : ctx_(other.ctx_), cmd_(std::exchange(other.cmd_, VK_NULL_HANDLE)), finished_(other.finished_),
      marks_(std::exchange(other.marks_, {})) {}

Recorder::~Recorder() {
  // A recorder dropped without being submitted frees its command buffer right away.
  if (cmd_ != VK_NULL_HANDLE && !finished_) {
    vkFreeCommandBuffers(ctx_->device(), ctx_->command_pool(), 1, &cmd_);
    ctx_->recorder_closed();
    if (StageTimer* t = ctx_->stage_timer()) t->dropped(std::move(marks_));
  }
}

void Recorder::mark_stage() {
  if (StageTimer* t = ctx_->stage_timer()) t->mark(*this, marks_);
}

VkCommandBuffer Recorder::finish() {
  if (finished_ || cmd_ == VK_NULL_HANDLE) throw std::logic_error("command buffer submitted twice");
  if (StageTimer* t = ctx_->stage_timer()) t->close(*this, marks_);
  // A host wait alone does not make device writes visible to host reads of mapped memory.
  VkMemoryBarrier to_host{.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
  S4D_VK_CHECK(vkEndCommandBuffer(cmd_));
  ctx_->recorder_closed();
  finished_ = true;
  return cmd_;
}

Groups Recorder::split_groups(uint32_t flat_groups) const {
  const DeviceInfo& info = ctx_->info();
  const uint32_t cap = ctx_->max_groups_x();
  const uint32_t max_x = cap ? std::min(cap, info.max_workgroup_count[0]) : info.max_workgroup_count[0];
  if (flat_groups <= max_x) return {flat_groups, 1, 1};
  const uint32_t y = static_cast<uint32_t>((uint64_t{flat_groups} + max_x - 1) / max_x);
  if (y > info.max_workgroup_count[1])
    throw std::invalid_argument("dispatch of " + std::to_string(flat_groups) + " workgroups exceeds " + info.name +
                                "'s 2-D grid limit (" + std::to_string(max_x) + " x " +
                                std::to_string(info.max_workgroup_count[1]) + ")");
  // Spread evenly so the overshoot past flat_groups stays below one row.
  const uint32_t x = static_cast<uint32_t>((uint64_t{flat_groups} + y - 1) / y);
  return {x, y, 1};
}

namespace {

// Lower case without underscores.
std::string folded(std::string_view s) {
  std::string out;
  for (char c : s)
    if (c != '_') out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return out;
}

// bindings ordered by binding number, each checked against the pipeline's reflected layout.
std::vector<const Binding*> by_binding(const Pipeline& pipeline, std::span<const Binding> bindings) {
  const std::vector<DescriptorBinding>& layout = pipeline.reflection().bindings;
  const auto who = [&] { return "dispatch of '" + pipeline.name() + "': "; };
  std::vector<const Binding*> slots(layout.size(), nullptr);
  for (const Binding& b : bindings) {
    if (b.id >= layout.size())
      throw std::invalid_argument(
          who() + b.name + " is binding " + std::to_string(b.id) + ", but the shader declares " +
          (layout.empty() ? "no bindings" : "bindings 0.." + std::to_string(layout.size() - 1)));
    if (slots[b.id])
      throw std::invalid_argument(who() + "binding " + std::to_string(b.id) + " is bound twice, as " +
                                  slots[b.id]->name + " and as " + b.name);
    if (!binding_name_agrees(b.name, layout[b.id].block))
      throw std::invalid_argument(who() + b.name + " is binding " + std::to_string(b.id) +
                                  ", where the shader declares block '" + layout[b.id].block +
                                  "': an id of another kernel?");
    slots[b.id] = &b;
  }
  for (size_t i = 0; i < slots.size(); ++i)
    if (!slots[i])
      throw std::invalid_argument(who() + "binding " + std::to_string(i) + " (block '" + layout[i].block +
                                  "') is not bound");
  return slots;
}

// by_binding, and the push-constant size checked against the shader's.
std::vector<const Binding*> checked_slots(const Pipeline& pipeline, std::span<const Binding> bindings,
                                          size_t params_bytes) {
  std::vector<const Binding*> slots = by_binding(pipeline, bindings);
  if (params_bytes != pipeline.push_constant_bytes())
    throw std::invalid_argument("dispatch of '" + pipeline.name() + "': push constants are " + std::to_string(params_bytes) +
                                " bytes, the shader declares " + std::to_string(pipeline.push_constant_bytes()));
  return slots;
}

}  // namespace

bool binding_name_agrees(std::string_view id_name, std::string_view block) {
  const auto is_in_out = [](std::string_view w) { return w == "In" || w == "Out"; };
  const auto word_end = [&](size_t i) {
    do ++i;
    while (i < block.size() && !std::isupper(static_cast<unsigned char>(block[i])));
    return i;
  };
  if (!block.empty() && is_in_out(block.substr(0, word_end(0)))) block.remove_prefix(word_end(0));
  size_t last = 0;
  for (size_t i = 0; i < block.size(); i = word_end(i)) last = i;
  if (is_in_out(block.substr(last))) block.remove_suffix(block.size() - last);
  if (id_name.starts_with("S4D_B_")) id_name.remove_prefix(6);
  return folded(id_name).find(folded(block)) != std::string::npos;
}

void Recorder::bind(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params,
                    size_t params_bytes) {
  const std::vector<const Binding*> slots = checked_slots(pipeline, bindings, params_bytes);
  std::vector<VkDescriptorBufferInfo> infos(slots.size());
  std::vector<VkWriteDescriptorSet> writes(slots.size());
  for (size_t i = 0; i < slots.size(); ++i) {
    const BufferRange& r = slots[i]->range;
    const auto who = [&] { return "dispatch of '" + pipeline.name() + "': " + slots[i]->name; };
    if (!r.buffer || !r.buffer->valid()) throw std::invalid_argument(who() + " has no buffer");
    if (r.buffer->kind() != BufferKind::storage)
      throw std::invalid_argument(who() + ": buffer '" + r.buffer->name() +
                                  "' is a staging buffer and cannot be bound to a shader");
    // An empty Buffer (size 0) still has a small allocation and binds whole at offset 0.
    const bool empty_whole = r.buffer->size() == 0 && r.offset == 0 && r.bytes == 0;
    if (!empty_whole && (r.offset >= r.buffer->size() || r.bytes > r.buffer->size() - r.offset))
      throw std::invalid_argument(who() + ": range overruns buffer '" + r.buffer->name() + "'");
    const uint64_t align = ctx_->info().min_storage_buffer_offset_alignment;
    if (align > 1 && r.offset % align != 0)
      throw std::invalid_argument(who() + ": buffer '" + r.buffer->name() + "' starts at offset " +
                                  std::to_string(r.offset) + ", not a multiple of minStorageBufferOffsetAlignment (" +
                                  std::to_string(align) + ")");
    infos[i] = {.buffer = r.buffer->handle(), .offset = r.offset, .range = r.bytes ? r.bytes : VK_WHOLE_SIZE};
    writes[i] = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                 .dstBinding = static_cast<uint32_t>(i),
                 .descriptorCount = 1,
                 .descriptorType = pipeline.reflection().bindings[i].storage_buffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                                                                    : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                 .pBufferInfo = &infos[i]};
  }
  mark_stage();
  begin_label(pipeline.name());
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
  if (!writes.empty())
    ctx_->cmd_push_descriptor_set()(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0,
                                    static_cast<uint32_t>(writes.size()), writes.data());
  if (params_bytes)
    vkCmdPushConstants(cmd_, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<uint32_t>(params_bytes), params);
}

void Recorder::dispatch_raw(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params,
                            size_t params_bytes, uint32_t flat_groups) {
  if (flat_groups == 0) {  // still checked: a wrong binding should not hide behind an empty dispatch
    (void)checked_slots(pipeline, bindings, params_bytes);
    return;
  }
  const Groups g = split_groups(flat_groups);
  bind(pipeline, bindings, params, params_bytes);
  vkCmdDispatch(cmd_, g.x, g.y, g.z);
  end_label();
  ctx_->note_op(pipeline.name());
}

void Recorder::dispatch_indirect_raw(const Pipeline& pipeline, std::span<const Binding> bindings, const void* params,
                                     size_t params_bytes, const Buffer& args, size_t offset) {
  if (!args.valid() || args.kind() != BufferKind::storage)
    throw std::invalid_argument("indirect dispatch of '" + pipeline.name() + "': argument buffer '" + args.name() +
                                "' must be a device (storage) buffer");
  if (offset % 4 != 0 || offset > args.size() || args.size() - offset < sizeof(VkDispatchIndirectCommand))
    throw std::invalid_argument("indirect dispatch of '" + pipeline.name() + "': arguments at offset " +
                                std::to_string(offset) + " must be 4-byte aligned and inside buffer '" + args.name() + "'");
  bind(pipeline, bindings, params, params_bytes);
  vkCmdDispatchIndirect(cmd_, args.handle(), offset);
  end_label();
  ctx_->note_op(pipeline.name());
}

void Recorder::barrier() {
  mark_stage();
  VkMemoryBarrier mb{.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                     .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                     .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                      VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                                      VK_ACCESS_INDIRECT_COMMAND_READ_BIT};
  const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(cmd_, stages, stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

void Recorder::copy(const Buffer& src, const Buffer& dst, size_t bytes, size_t src_offset, size_t dst_offset) {
  if (src_offset > src.size() || bytes > src.size() - src_offset || dst_offset > dst.size() || bytes > dst.size() - dst_offset)
    throw std::invalid_argument("copy of " + std::to_string(bytes) + " bytes from '" + src.name() + "' to '" + dst.name() +
                                "' overruns a buffer");
  if (bytes == 0) return;
  mark_stage();
  VkBufferCopy region{.srcOffset = src_offset, .dstOffset = dst_offset, .size = bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
}

void Recorder::fill(const Buffer& dst, uint32_t value, size_t bytes, size_t offset) {
  if (offset > dst.size() || bytes > dst.size() - offset || bytes % 4 || offset % 4)
    throw std::invalid_argument("fill of buffer '" + dst.name() + "': range must be 4-byte aligned and inside the buffer");
  if (bytes == 0) bytes = dst.size() - offset;
  if (bytes % 4)
    throw std::invalid_argument("fill of buffer '" + dst.name() + "': range must be 4-byte aligned and inside the buffer");
  if (bytes == 0) return;
  mark_stage();
  vkCmdFillBuffer(cmd_, dst.handle(), offset, bytes, value);
}

void Recorder::reset_queries(TimestampQueries& queries) { vkCmdResetQueryPool(cmd_, queries.handle(), 0, queries.count()); }

void Recorder::timestamp(TimestampQueries& queries, uint32_t index) {
  vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.handle(), index);
}

void Recorder::begin_label(const std::string& label) {
  if (!ctx_->cmd_begin_label()) return;
  VkDebugUtilsLabelEXT l{.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT, .pLabelName = label.c_str()};
  ctx_->cmd_begin_label()(cmd_, &l);
}

void Recorder::end_label() {
  if (ctx_->cmd_end_label()) ctx_->cmd_end_label()(cmd_);
}

}  // namespace s4d::engine
