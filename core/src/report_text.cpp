// Human-readable reports: report.csv, report.md, the terminal table and the
// aggregate of a batch. Values are fractions in the CSV, x100 elsewhere (as in the paper).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>

#include "lom/labels.hpp"
#include "lom/report.hpp"
#include "lom/text_columns.hpp"

namespace lom {

namespace {

constexpr const char* kMethodNames[3] = {"Projection (Mean)", "Projection (Max)", "LabelOctoMap"};

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", fraction * 100.0);
  return text;
}

std::string cubicCentimetres(double cubic_metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", std::max(cubic_metres, 0.0) * 1e6);
  return text;
}

std::string fraction(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6f", value);
  return text;
}

std::vector<double> values(const MethodScores& s) { return {s.projection_mean, s.projection_max, s.labeloctomap}; }

// Markdown cells x100 with the best bold. Values equal after rounding are all
// bold; nothing is bold when every value is below 1 (as the paper's table).
std::vector<std::string> markBest(const MethodScores& scores) {
  std::vector<std::string> cells;
  for (double v : values(scores)) cells.push_back(percent(v));
  const auto best = std::max_element(cells.begin(), cells.end(),
                                     [](const std::string& a, const std::string& b) { return std::stod(a) < std::stod(b); });
  if (std::stod(*best) < 1.0) return cells;
  const std::string best_text = *best;
  for (auto& cell : cells)
    if (cell == best_text) cell = "**" + cell + "**";
  return cells;
}

std::string markdownText(const std::string& text) {
  std::string out;
  for (char c : singleLineText(text)) {  // a line break would end the table row
    if (c == '|' || c == '*' || c == '_' || c == '\\' || c == '`') out += '\\';
    out += c;
  }
  return out;
}

// A relative link target: bytes that would end or break the link (spaces,
// brackets, '|' of the table, '%', control and non-ASCII bytes) percent-encoded,
// as URLs write them.
std::string markdownLinkTarget(const std::string& path) {
  static const char* const kHex = "0123456789ABCDEF";
  std::string out;
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || std::strchr("/._-~", c)) {
      out += c;
    } else {
      out += '%';
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

std::string csvText(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// The views' frames; many (a view every few frames of a long recording)
// are told by the first few and the last, so that the settings stay a line
// (report.json lists them all).
std::string joinViews(const std::vector<size_t>& views) {
  constexpr size_t kNamed = 3;
  std::string text;
  for (size_t i = 0; i < views.size(); ++i) {
    if (views.size() > 2 * kNamed && i == kNamed) {
      text += ", ... " + std::to_string(views.back());
      break;
    }
    text += (text.empty() ? "" : ", ") + std::to_string(views[i]);
  }
  return text;
}

std::string describeSettings(const EvaluationReport& r) {
  std::ostringstream out;
  out << "resolution " << r.resolution << " m, max range ";
  if (r.max_range > 0.0) out << r.max_range << " m";
  else out << "unlimited";
  out << ", occupancy threshold " << r.occupancy_threshold << ", p_miss " << r.p_miss;
  if (r.fused_frames) {
    if (r.fused_frames->first == r.fused_frames->second)
      out << ", frame " << r.fused_frames->first << " fused";
    else
      out << ", frames " << r.fused_frames->first << "-" << r.fused_frames->second << " fused";
  }
  if (!r.segmenter.empty()) out << " (segmenter " << r.segmenter << ")";
  out << ", IU_3d from "
      << (r.iou_mode == IouMode::Exact ? "exact voxel/box intersection volumes"
                                       : "voxel centres inside the box")
      << ", " << r.views.size() << (r.views.size() == 1 ? " view (frame " : " views (frames ")
      << joinViews(r.views) << ")";
  if (r.candidates) {
    std::string list;
    for (int c : *r.candidates) list += (list.empty() ? "" : ",") + std::to_string(c);
    out << ", candidates " << list;
  }
  return out.str();
}

// Ascending frame indices as runs ("0-49, 52"): a long recording stays one line.
std::string frameRuns(const std::vector<size_t>& frames) {
  std::string text;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    text += (text.empty() ? "" : ", ") + std::to_string(frames[i]);
    if (j > i) text += "-" + std::to_string(frames[j]);
    i = j + 1;
  }
  return text;
}

// Frames left out of the 2D metrics, for a report (empty when none was).
std::string excludedFramesText(const EvaluationReport& r) {
  const size_t n = r.metrics_2d_excluded_frames.size();
  if (n == 0) return {};
  return std::to_string(n) + (n == 1 ? " frame" : " frames") + " (" +
         frameRuns(r.metrics_2d_excluded_frames) + ") left out: " +
         (n == 1 ? "its probabilities were made from its label image"
                 : "their probabilities were made from their label images");
}

void markdownMetricsRow(std::ostringstream& out, const char* name, const Metrics2d& m) {
  out << "| " << name << " | " << percent(m.pixel_accuracy) << " | " << percent(m.mean_accuracy) << " | "
      << percent(m.mean_iu) << " | " << percent(m.fw_iu) << " |\n";
}

std::string tableScores(const MethodScores& s) {
  return padLeft(percent(s.projection_mean), 11) + padLeft(percent(s.projection_max), 10) +
         padLeft(percent(s.labeloctomap), 14);
}

}  // namespace

std::string reportCsv(const EvaluationReport& report) {
  std::ostringstream out;
  out << "label,name,voxels,iou3d_projection_mean,iou3d_projection_max,iou3d_labeloctomap,"
         "box_iou_projection_mean,box_iou_projection_max,box_iou_labeloctomap";
  for (size_t v : report.views) out << ",iou3d_frame_" << v;
  for (size_t v : report.views) out << ",box_iou_frame_" << v;
  out << "\n";
  for (const auto& o : report.objects) {
    out << o.label << "," << csvText(o.name) << "," << o.voxels;
    for (double v : values(o.iou_3d)) out << "," << fraction(v);
    for (double v : values(o.box_iou)) out << "," << fraction(v);
    for (double v : o.per_view) out << "," << fraction(v);
    for (double v : o.per_view_box_iou) out << "," << fraction(v);
    out << "\n";
  }
  return out.str();
}

std::string aggregateCsv(const std::vector<EvaluationReport>& reports) {
  std::ostringstream out;
  out << "sequence,label,name,voxels,iou3d_projection_mean,iou3d_projection_max,"
         "iou3d_labeloctomap,box_iou_projection_mean,box_iou_projection_max,"
         "box_iou_labeloctomap\n";
  for (const EvaluationReport& report : reports)
    for (const auto& o : report.objects) {
      out << csvText(report.sequence) << "," << o.label << "," << csvText(o.name) << ","
          << o.voxels;
      for (double v : values(o.iou_3d)) out << "," << fraction(v);
      for (double v : values(o.box_iou)) out << "," << fraction(v);
      out << "\n";
    }
  return out.str();
}

std::string reportMarkdown(const EvaluationReport& report) {
  std::ostringstream out;
  out << "# Segmentation results: " << markdownText(report.sequence) << "\n\n"
      << markdownText(describeSettings(report)) << ".\n"
      << "Map: "
      << (report.map_file.empty() ? std::string("fused from the sequence with these settings")
                                  : markdownText(report.map_file))
      << ".\n";
  if (!report.warnings.empty()) {
    out << "\n**Warnings**\n\n";
    for (const std::string& warning : report.warnings) out << "- " << markdownText(warning) << "\n";
  }
  out << "\nValues are x100; the best of each row is bold (none when all are below 1).\n\n"
      << "## IU_3d per object\n\n"
      << "| label | name | voxels | Projection (Mean) | Projection (Max) | LabelOctoMap |\n"
      << "|---:|---|---:|---:|---:|---:|\n";
  for (const auto& o : report.objects) {
    const auto cells = markBest(o.iou_3d);
    out << "| " << o.label << " | " << markdownText(o.name) << " | " << o.voxels << " | " << cells[0] << " | "
        << cells[1] << " | " << cells[2] << " |\n";
  }
  const ScoreSummary& s = report.summary;
  out << "\n## Summary\n\n| methods | mean IU_3d | mean box IU |\n|---|---:|---:|\n";
  const auto iou_cells = markBest(s.iou_3d);
  const auto box_cells = markBest(s.box_iou);
  for (int m = 0; m < 3; ++m)
    out << "| " << kMethodNames[m] << " | " << iou_cells[static_cast<size_t>(m)] << " | "
        << box_cells[static_cast<size_t>(m)] << " |\n";
  out << "\nLabelOctoMap exceeds Projection (Max) for " << s.labeloctomap_beats_projection_max
      << " of " << s.objects << " objects.\n\n![IU_3d per object](report.svg)\n\n"
      << "## LabelOctoMap's IU_3d in volumes\n\n"
      << "In cm³: the voxels' volume inside the box (true positive), outside it (false positive) "
         "and "
         "the box's volume without voxels (false negative; mostly the inside of objects, which no "
         "camera sees).\n\n"
      << "| label | name | inside the box | outside | box not covered | box |\n"
      << "|---:|---|---:|---:|---:|---:|\n";
  for (const auto& o : report.objects) {
    const IouVolumes& v = o.labeloctomap_volumes;
    out << "| " << o.label << " | " << markdownText(o.name) << " | "
        << cubicCentimetres(v.true_positive) << " | " << cubicCentimetres(v.falsePositive())
        << " | " << cubicCentimetres(v.falseNegative()) << " | " << cubicCentimetres(v.ground_truth)
        << " |\n";
  }
  out << "\n## Box IU per object\n\nBoxes fitted to the largest cluster of each method's "
         "voxels.\n\n"
      << "| label | name | Projection (Mean) | Projection (Max) | LabelOctoMap "
         "|\n|---:|---|---:|---:|---:|\n";
  for (const auto& o : report.objects) {
    const auto cells = markBest(o.box_iou);
    out << "| " << o.label << " | " << markdownText(o.name) << " | " << cells[0] << " | " << cells[1] << " | "
        << cells[2] << " |\n";
  }
  if (report.metrics_2d) {
    out << "\n## 2D segmentation\n\nOver " << report.metrics_2d->pixels << " labelled pixels, "
        << report.metrics_2d->classes << " classes in the ground truth.\n\n"
        << "| candidates | pixel acc. | mean acc. | mean IU | f.w. IU |\n|---|---:|---:|---:|---:|\n";
    markdownMetricsRow(out, "no", *report.metrics_2d);
    if (report.metrics_2d_candidates) markdownMetricsRow(out, "yes", *report.metrics_2d_candidates);
    if (const std::string excluded = excludedFramesText(report); !excluded.empty())
      out << "\n" << markdownText(excluded) << ".\n";
  } else if (!report.metrics_2d_not_scored.empty()) {
    out << "\n## 2D segmentation\n\nNot scored: " << markdownText(report.metrics_2d_not_scored)
        << ".\n";
  }
  return out.str();
}

std::string reportTable(const EvaluationReport& report) {
  std::ostringstream out;
  out << "Segmentation results (IU_3d x100) of " << report.sequence << ": " << describeSettings(report) << "\n"
      << padLeft("label", 6) << "  " << padRight("name", 36) << padLeft("voxels", 8) << padLeft("Proj Mean", 11)
      << padLeft("Proj Max", 10) << padLeft("LabelOctoMap", 14) << "\n";
  for (const auto& o : report.objects)
    out << padLeft(std::to_string(o.label), 6) << "  " << padRight(o.name, 36)
        << padLeft(std::to_string(o.voxels), 8) << tableScores(o.iou_3d) << "\n";
  const ScoreSummary& s = report.summary;
  out << padRight("Summary (" + std::to_string(s.objects) + " objects)", 52) << tableScores(s.iou_3d) << "\n"
      << padRight("Box IU (mean)", 52) << tableScores(s.box_iou) << "\n"
      << "LabelOctoMap exceeds Projection (Max) for " << s.labeloctomap_beats_projection_max << " of "
      << s.objects << " objects\n";
  auto metrics = [&](const char* name, const Metrics2d& m) {
    out << "2D segmentation " << name << ": pixel acc. " << percent(m.pixel_accuracy) << ", mean acc. "
        << percent(m.mean_accuracy) << ", mean IU " << percent(m.mean_iu) << ", f.w. IU " << percent(m.fw_iu)
        << "\n";
  };
  if (report.metrics_2d) metrics("without candidates", *report.metrics_2d);
  if (report.metrics_2d_candidates) metrics("with candidates", *report.metrics_2d_candidates);
  if (report.metrics_2d) {
    if (const std::string excluded = excludedFramesText(report); !excluded.empty())
      out << "2D segmentation: " << excluded << "\n";
  } else if (!report.metrics_2d_not_scored.empty()) {
    out << "2D segmentation: not scored: " << report.metrics_2d_not_scored << "\n";
  }
  return out.str();
}

std::vector<std::string> mixedSettingsWarnings(const std::vector<EvaluationReport>& reports) {
  auto number = [](double value, const char* unit) {
    std::ostringstream text;
    text << value << unit;
    return text.str();
  };
  const struct {
    const char* what;
    std::function<std::string(const EvaluationReport&)> value;
  } settings[] = {
      {"resolution", [&](const EvaluationReport& r) { return number(r.resolution, " m"); }},
      {"max range",
       [&](const EvaluationReport& r) {
         return r.max_range > 0.0 ? number(r.max_range, " m") : std::string("unlimited");
       }},
      {"occupancy threshold",
       [&](const EvaluationReport& r) { return number(r.occupancy_threshold, ""); }},
      {"p_miss", [&](const EvaluationReport& r) { return number(r.p_miss, ""); }},
      {"IU_3d mode",
       [](const EvaluationReport& r) { return std::string(iouModeName(r.iou_mode)); }},
      {"segmenter",
       [](const EvaluationReport& r) {
         return r.segmenter.empty() ? std::string("none")
                                    : std::filesystem::path(r.segmenter).filename().string();
       }},
  };
  std::vector<std::string> warnings;
  for (const auto& setting : settings) {
    // Each value with the sequences that have it, in the batch's order.
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;
    for (const EvaluationReport& r : reports) {
      const std::string value = setting.value(r);
      auto group = std::find_if(groups.begin(), groups.end(),
                                [&](const auto& g) { return g.first == value; });
      if (group == groups.end()) group = groups.insert(groups.end(), {value, {}});
      group->second.push_back(r.sequence);
    }
    if (groups.size() < 2) continue;
    std::string list;
    for (const auto& [value, names] : groups) {
      std::string who;
      for (size_t i = 0; i < names.size() && i < 3; ++i) who += (i ? ", " : "") + names[i];
      if (names.size() > 3) who += " and " + std::to_string(names.size() - 3) + " more";
      list += (list.empty() ? "" : "; ") + value + " (" + who + ")";
    }
    warnings.push_back("the sequences were scored at different " + std::string(setting.what) +
                       "s: " + list +
                       "; the \"all\" row averages scores that are not comparable (score them "
                       "at one setting)");
  }
  return warnings;
}

std::string aggregateMarkdown(const std::vector<EvaluationReport>& reports) {
  std::ostringstream out;
  out << "# Segmentation results of " << reports.size() << " sequences\n\n"
      << "Mean IU_3d x100 over the objects of each sequence; the last row is the mean over all "
         "objects.\n\n";
  // The settings, when the sequences share them (else the warnings say how they differ).
  if (!reports.empty()) {
    const EvaluationReport& first = reports.front();
    auto shared = [&](auto get) {
      return std::all_of(reports.begin(), reports.end(),
                         [&](const EvaluationReport& r) { return get(r) == get(first); });
    };
    std::vector<std::string> parts;
    std::ostringstream value;
    auto add = [&](const std::string& text) { parts.push_back(text); };
    if (shared([](const EvaluationReport& r) { return r.resolution; })) {
      value.str("");
      value << first.resolution * 100.0 << " cm voxels";
      add(value.str());
    }
    if (shared([](const EvaluationReport& r) { return r.max_range; })) {
      value.str("");
      if (first.max_range > 0.0)
        value << "max range " << first.max_range << " m";
      else
        value << "no range limit";
      add(value.str());
    }
    if (shared([](const EvaluationReport& r) { return r.occupancy_threshold; })) {
      value.str("");
      value << "threshold " << first.occupancy_threshold;
      add(value.str());
    }
    if (shared([](const EvaluationReport& r) { return r.p_miss; })) {
      value.str("");
      value << "p_miss " << first.p_miss;
      add(value.str());
    }
    if (shared([](const EvaluationReport& r) { return r.iou_mode; }))
      add(std::string("IU_3d ") + iouModeName(first.iou_mode));
    std::string line;
    for (const std::string& part : parts) line += (line.empty() ? "" : ", ") + part;
    if (!line.empty()) out << "Settings of every sequence: " << line << ".\n\n";
  }
  out << "| sequence | objects | Projection (Mean) | Projection (Max) | LabelOctoMap | "
         "LabelOctoMap > Projection (Max) |\n"
      << "|---|---:|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& name, const ScoreSummary& s) {
    const auto cells = markBest(s.iou_3d);
    out << "| " << name << " | " << s.objects << " | " << cells[0] << " | " << cells[1] << " | " << cells[2]
        << " | " << s.labeloctomap_beats_projection_max << " |\n";
  };
  for (const auto& r : reports)
    row("[" + markdownText(r.sequence) + "](" + markdownLinkTarget(r.sequence + "/report.md") + ")",
        r.summary);
  row("all", summarizeAll(reports));
  out << "\n![Mean IU_3d per sequence](aggregate.svg)\n";
  // Each sequence's warnings, so that a doubtful row is not read as a good one.
  const std::vector<std::string> mixed = mixedSettingsWarnings(reports);
  bool any = !mixed.empty();
  for (const auto& r : reports) any = any || !r.warnings.empty();
  if (any) {
    out << "\n**Warnings**\n";
    if (!mixed.empty()) {
      out << "\nall:\n\n";
      for (const std::string& warning : mixed) out << "- " << markdownText(warning) << "\n";
    }
    for (const auto& r : reports) {
      if (r.warnings.empty()) continue;
      out << "\n" << markdownText(r.sequence) << ":\n\n";
      for (const std::string& warning : r.warnings) out << "- " << markdownText(warning) << "\n";
    }
  }
  return out.str();
}

std::string aggregateTable(const std::vector<EvaluationReport>& reports) {
  std::ostringstream out;
  out << "Mean IU_3d x100 per sequence\n"
      << padRight("sequence", 36) << padLeft("objects", 8) << padLeft("Proj Mean", 11) << padLeft("Proj Max", 10)
      << padLeft("LabelOctoMap", 14) << "\n";
  for (const auto& r : reports)
    out << padRight(r.sequence, 36) << padLeft(std::to_string(r.summary.objects), 8) << tableScores(r.summary.iou_3d)
        << "\n";
  const ScoreSummary all = summarizeAll(reports);
  out << padRight("all", 36) << padLeft(std::to_string(all.objects), 8) << tableScores(all.iou_3d) << "\n"
      << "LabelOctoMap exceeds Projection (Max) for " << all.labeloctomap_beats_projection_max << " of "
      << all.objects << " objects\n";
  return out.str();
}

}  // namespace lom
