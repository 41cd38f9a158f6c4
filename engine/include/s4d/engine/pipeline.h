// A compute pipeline built from SPIR-V. Its descriptor-set layout, push-constant range and
// workgroup size come from reflecting the module, so the host never restates them by hand.
#pragma once
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/spirv_reflect.h"

namespace s4d::engine {

class Pipeline {
 public:
  Pipeline(Context& ctx, std::string name, std::span<const uint32_t> spirv, const std::vector<SpecConstant>& spec);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  const std::string& name() const { return name_; }
  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  uint32_t binding_count() const { return static_cast<uint32_t>(reflection_.bindings.size()); }
  uint32_t push_constant_bytes() const { return reflection_.push_constant_bytes; }
  const uint32_t* local_size() const { return reflection_.local_size; }
  const ModuleReflection& reflection() const { return reflection_; }

 private:
  Context& ctx_;
  std::string name_;
  ModuleReflection reflection_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace s4d::engine
