// The rule by which dispatch checks a binding id's name against the shader's block at that binding
// (s4d::engine::binding_name_agrees), and proof that every id in the shader sources meets it, so no
// kernel path, however rarely taken (the CAS fallbacks, say), can throw on it at run time.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>

#include "s4d/engine/recorder.h"

using s4d::engine::binding_name_agrees;

TEST_CASE("a binding id agrees with its block's name, less a leading or trailing In or Out") {
  CHECK(binding_name_agrees("S4D_B_ADAM_PARAMS", "Params"));
  CHECK(binding_name_agrees("S4D_B_RASTER_RGB", "OutRgb"));
  CHECK(binding_name_agrees("S4D_B_RADIX_COUNT_KEYS", "KeysIn"));
  CHECK(binding_name_agrees("S4D_B_SSIM_H_IN_A", "InA"));
  CHECK(binding_name_agrees("S4D_B_LOSS_GRAD_DMAPS_H", "DMapsH"));
  CHECK(binding_name_agrees("S4D_B_DBWD_V_OPACITY_LOGITS", "VOpacity"));
  CHECK(binding_name_agrees("S4D_B_IOTA_OUT", ""));  // a module stripped of names
}

TEST_CASE("a binding id of another kernel disagrees with the block's name") {
  CHECK_FALSE(binding_name_agrees("S4D_B_ADD_DST", "Groups"));
  CHECK_FALSE(binding_name_agrees("S4D_B_MASK_ROWS", "Src"));
  CHECK_FALSE(binding_name_agrees("S4D_B_RASTER_RGB", "OutAlpha"));
  CHECK_FALSE(binding_name_agrees("S4D_B_CONV_IN", "Weight"));
  CHECK_FALSE(binding_name_agrees("S4D_B_RADIX_KEYS_IN", "ValuesIn"));
  CHECK_FALSE(binding_name_agrees("S4D_B_RANGES_OUT", "OutRgbOut"));  // only In/Out at the ends drop
}

TEST_CASE("every binding id in the shader sources agrees with the block it declares") {
  const std::regex binding_line(
      R"(binding\s*=\s*(S4D_B_\w+)\s*\)\s*(?:(?:readonly|writeonly|restrict|coherent)\s+)*(?:buffer|uniform)\s+(\w+))");
  size_t declarations = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(S4D_SOURCE_DIR "/shaders")) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".comp" && ext != ".glsl") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string source = text.str();
    const std::regex any_binding(R"(binding\s*=)");
    const auto bindings = static_cast<size_t>(
        std::distance(std::sregex_iterator(source.begin(), source.end(), any_binding), std::sregex_iterator()));
    size_t matched = 0;
    for (std::sregex_iterator it(source.begin(), source.end(), binding_line), end; it != end; ++it, ++matched)
      CHECK_MESSAGE(binding_name_agrees((*it)[1].str(), (*it)[2].str()),
                    entry.path().filename().string() << ": " << (*it)[1] << " declares block " << (*it)[2]);
    // Every "binding =" is a declaration this test read, so none escapes the check.
    CHECK_MESSAGE(matched == bindings, entry.path().filename().string()
                                           << ": " << bindings - matched << " binding declarations not understood");
    declarations += matched;
  }
  CHECK(declarations > 200);
}
