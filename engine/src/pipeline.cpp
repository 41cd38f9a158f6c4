#include "s4d/engine/pipeline.h"

#include <stdexcept>

#include "s4d/engine/check.h"

namespace s4d::engine {

Pipeline::Pipeline(Context& ctx, std::string name, std::span<const uint32_t> spirv, const std::vector<SpecConstant>& spec)
    : ctx_(ctx), name_(std::move(name)), reflection_(reflect_spirv(spirv, name_)) {
  const DeviceInfo& info = ctx.info();
  if (reflection_.push_constant_bytes > info.max_push_constant_bytes)
    throw std::invalid_argument("shader '" + name_ + "' needs " + std::to_string(reflection_.push_constant_bytes) +
                                " bytes of push constants; " + info.name + " allows " +
                                std::to_string(info.max_push_constant_bytes));
  const uint32_t* ls = reflection_.local_size;
  for (int i = 0; i < 3; ++i)
    if (ls[i] > info.max_workgroup_size[i])
      throw std::invalid_argument("shader '" + name_ + "' has workgroup size " + std::to_string(ls[i]) + " along axis " +
                                  std::to_string(i) + "; " + info.name + " allows " + std::to_string(info.max_workgroup_size[i]));
  if (ls[0] * ls[1] * ls[2] > info.max_workgroup_invocations)
    throw std::invalid_argument("shader '" + name_ + "' has " + std::to_string(ls[0] * ls[1] * ls[2]) +
                                " invocations per workgroup; " + info.name + " allows " +
                                std::to_string(info.max_workgroup_invocations));

  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (const auto& b : reflection_.bindings) {
    if (b.set != 0) throw std::invalid_argument("shader '" + name_ + "' uses descriptor set " + std::to_string(b.set) + "; only set 0 is supported");
    if (b.binding != bindings.size())
      throw std::invalid_argument("shader '" + name_ + "' bindings must be 0..n-1 without gaps (found binding " +
                                  std::to_string(b.binding) + ")");
    bindings.push_back({.binding = b.binding,
                        .descriptorType = b.storage_buffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                        .descriptorCount = 1,
                        .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT});
  }
  const std::string ctx_text = "creating pipeline '" + name_ + "'";
  VkShaderModuleCreateInfo smci{.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                .codeSize = spirv.size_bytes(),
                                .pCode = spirv.data()};
  S4D_VK_CHECK_CTX(vkCreateShaderModule(ctx.device(), &smci, nullptr, &module_), ctx_text);
  ctx.set_name(VK_OBJECT_TYPE_SHADER_MODULE, reinterpret_cast<uint64_t>(module_), name_);

  VkDescriptorSetLayoutCreateInfo dslci{.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
                                        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
                                        .bindingCount = static_cast<uint32_t>(bindings.size()),
                                        .pBindings = bindings.data()};
  S4D_VK_CHECK_CTX(vkCreateDescriptorSetLayout(ctx.device(), &dslci, nullptr, &set_layout_), ctx_text);
  ctx.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, reinterpret_cast<uint64_t>(set_layout_), name_ + " set layout");

  VkPushConstantRange range{.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .offset = 0, .size = reflection_.push_constant_bytes};
  VkPipelineLayoutCreateInfo plci{.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                  .setLayoutCount = 1,
                                  .pSetLayouts = &set_layout_,
                                  .pushConstantRangeCount = range.size ? 1u : 0u,
                                  .pPushConstantRanges = &range};
  S4D_VK_CHECK_CTX(vkCreatePipelineLayout(ctx.device(), &plci, nullptr, &layout_), ctx_text);
  ctx.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, reinterpret_cast<uint64_t>(layout_), name_ + " layout");

  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (const auto& s : spec) {
    entries.push_back({.constantID = s.id, .offset = static_cast<uint32_t>(values.size() * 4), .size = 4});
    values.push_back(s.value);
  }
  VkSpecializationInfo si{.mapEntryCount = static_cast<uint32_t>(entries.size()),
                          .pMapEntries = entries.data(),
                          .dataSize = values.size() * 4,
                          .pData = values.data()};
  VkComputePipelineCreateInfo cpci{.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
                                   .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                                             .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                                             .module = module_,
                                             .pName = "main",
                                             .pSpecializationInfo = spec.empty() ? nullptr : &si},
                                   .layout = layout_};
  S4D_VK_CHECK_CTX(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline_), ctx_text);
  ctx.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline_), name_);
}

Pipeline::~Pipeline() {
  VkDevice device = ctx_.device();
  VkPipeline pipeline = pipeline_;
  VkPipelineLayout layout = layout_;
  VkDescriptorSetLayout set_layout = set_layout_;
  VkShaderModule module = module_;
  ctx_.retire([=] {
    vkDestroyPipeline(device, pipeline, nullptr);
    vkDestroyPipelineLayout(device, layout, nullptr);
    vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    vkDestroyShaderModule(device, module, nullptr);
  });
}

}  // namespace s4d::engine
