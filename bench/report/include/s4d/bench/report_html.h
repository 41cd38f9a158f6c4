// report.html beside report.md: one self-contained page (no file or network fetched when opened)
// with the metric table (sortable; each metric's direction; "n/a, because ..." where a key is
// unavailable), the per-frame curves as inline SVG, the original and each method's video side by
// side playing in sync (WebM VP9 embedded as data: URLs, which Chromium, Firefox and Safari play), and
// the contact sheet.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>

namespace s4d::bench {

// The videos: frames mode the --original and each --frames sequence; run mode the spiral and the
// first test camera of the original render and each method. Sequences that no longer exist are
// named on the page instead. Throws std::runtime_error naming the file when it cannot be written.
void write_report_html(const std::filesystem::path& out, const nlohmann::json& report, int max_video_frames = 300);

}  // namespace s4d::bench
