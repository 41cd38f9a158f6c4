// The report contract of METRICS.md: the 14 keys `style4d bench` reports, each with its direction,
// implementation and convention, and for the learned ones, the reason they are unavailable when a
// call supplies neither their weights nor the pyiqa bridge.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace s4d::bench {

struct MetricEntry {
  std::string key;
  std::string label;      // column header in report.md
  bool higher_is_better;
  std::string impl;        // what computes it
  std::string convention;  // inputs, preprocessing, pooling
  // Set for the learned metrics: the "unavailable" text when neither --metric-weights nor the bridge
  // (--python) computed the key, naming what to supply.
  std::optional<std::string> unavailable;
};

// In the order of METRICS.md's table. The weight-free entries describe the defaults; the report
// writer overrides their convention text with the options actually used.
const std::vector<MetricEntry>& metric_catalog();

const MetricEntry& metric_entry(const std::string& key);  // throws std::out_of_range for an unknown key

}  // namespace s4d::bench
