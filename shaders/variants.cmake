# THE table of shader variants: "name|source|DEFINE=VALUE|...". Reviewed like code.
# A variant's name is its ShaderId (s4d::shaders::Id::<name>).
set(S4D_SHADER_VARIANTS
  "iota|util/iota.comp"
  "scan_reduce|scan/scan_reduce.comp"
  "scan_downsweep|scan/scan_downsweep.comp"
  "radix_count|sort/radix_count.comp"
  "radix_scatter|sort/radix_scatter.comp"
  "project_fwd|splat/project_fwd.comp"
  "count_tiles|splat/count_tiles.comp"
  "emit_instances|splat/emit_instances.comp"
  "tile_ranges|splat/tile_ranges.comp"
  "tile_list_stats|splat/tile_list_stats.comp"
  "raster_fwd|splat/raster_fwd.comp"
  "raster_bwd|splat/raster_bwd.comp|S4D_FLOAT_ATOMICS=1"
  "raster_bwd_cas|splat/raster_bwd.comp|S4D_FLOAT_ATOMICS=0"
  "project_bwd|splat/project_bwd.comp"
  "ssim_hpass|loss/ssim_hpass.comp"
  "ssim_vpass|loss/ssim_vpass.comp"
  "loss_grad|loss/loss_grad.comp"
  "adam_step|optim/adam_step.comp"
  "blend_ceiling|bench/blend_ceiling.comp"
)
