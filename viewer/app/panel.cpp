#include "panel.h"

#include <imgui.h>

namespace s4d::viewer {

namespace {

void section(const char* title) {  // ImGui 1.86 has no SeparatorText
  ImGui::Separator();
  ImGui::TextUnformatted(title);
}

}  // namespace

PanelActions draw_panel(const PanelInfo& info, Playback& playback, StyleSelection& styles) {
  PanelActions actions;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(300, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("style4d view");
  ImGui::Text("%s", info.device.c_str());
  ImGui::Text("%u Gaussians, %ux%u", info.gaussians, info.width, info.height);
  ImGui::Text("frame %.1f ms (render %.1f ms)", info.frame_ms, info.render_ms);
  ImGui::Text("rendered at %ux%u", info.render_width, info.render_height);

  section("time");
  float t = static_cast<float>(playback.time);
  if (ImGui::SliderFloat("t", &t, 0.0f, 1.0f, "%.3f")) playback.time = t;
  if (ImGui::Button(playback.playing ? "pause" : "play")) playback.playing = !playback.playing;
  ImGui::SameLine();
  ImGui::Checkbox("loop", &playback.loop);
  float speed = static_cast<float>(playback.speed);
  if (ImGui::SliderFloat("speed", &speed, 0.1f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic)) playback.speed = speed;
  if (!info.dynamic) ImGui::TextDisabled("static scene: the same at every time");

  section("style");
  const std::vector<std::string>& names = *info.styles;
  for (size_t i = 0; i < names.size(); ++i)
    if (ImGui::RadioButton(names[i].c_str(), styles.style == i)) styles.style = i;
  const char* mix = styles.mix < 0 ? "none" : names[static_cast<size_t>(styles.mix)].c_str();
  if (ImGui::BeginCombo("blend with", mix)) {
    if (ImGui::Selectable("none", styles.mix < 0)) styles.mix = -1;
    for (size_t i = 0; i < names.size(); ++i)
      if (ImGui::Selectable(names[i].c_str(), styles.mix == static_cast<int>(i))) styles.mix = static_cast<int>(i);
    ImGui::EndCombo();
  }
  if (styles.mix >= 0) ImGui::SliderFloat("factor ([ ])", &styles.alpha, 0.0f, 1.0f, "%.2f");

  section("cameras (keys 1-9, 0)");
  if (ImGui::BeginListBox("##cameras", ImVec2(-1, 6 * ImGui::GetTextLineHeightWithSpacing()))) {
    for (size_t i = 0; i < info.cameras->size(); ++i)
      if (ImGui::Selectable((std::to_string(i) + "  " + (*info.cameras)[i]).c_str(), false))
        actions.snap_camera = static_cast<int>(i);
    ImGui::EndListBox();
  }

  ImGui::Separator();
  actions.screenshot = ImGui::Button("screenshot (P)");
  ImGui::SameLine();
  actions.toggle_record = ImGui::Button(info.recording ? "stop path (R)" : "record path (R)");
  if (info.recording) ImGui::Text("recording: %zu frames", info.recorded);
  if (!info.message.empty()) ImGui::TextWrapped("%s", info.message.c_str());
  ImGui::End();
  return actions;
}

}  // namespace s4d::viewer
