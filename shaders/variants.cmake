# THE table of shader variants: "name|source|DEFINE=VALUE|...". Reviewed like code.
# A variant's name is its ShaderId (s4d::shaders::Id::<name>).
set(S4D_SHADER_VARIANTS
  "iota|util/iota.comp"
  "scan_reduce|scan/scan_reduce.comp"
  "scan_downsweep|scan/scan_downsweep.comp"
  "radix_count|sort/radix_count.comp"
  "radix_scatter|sort/radix_scatter.comp"
)
