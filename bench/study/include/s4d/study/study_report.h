// `style4d study report`: the paper's user-study tables from the votes. Participants who fail an
// attention check are left out and counted; per part, kind of pair (video or frame) and criterion:
// each method's share of the decisive votes with its 95 % Wilson interval, Bradley-Terry scores,
// and Krippendorff's alpha (nominal) between participants. docs/study.md.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "s4d/study/study_file.h"
#include "s4d/study/vote_store.h"

namespace s4d::study {

nlohmann::json study_report_json(const Study& study, const std::vector<Vote>& votes);

// OUT/study_report.json, study_report.csv and study_report.md.
void write_study_report(const std::filesystem::path& out, const nlohmann::json& report);

}  // namespace s4d::study
