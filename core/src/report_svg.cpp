// Grouped bar charts written as plain SVG text, so no display or plotting
// library is needed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "lom/labels.hpp"
#include "lom/report.hpp"

namespace lom {

namespace {

constexpr const char* kPalette[] = {"#9ecae1", "#3182bd", "#e6550d", "#31a354", "#756bb1", "#636363"};
constexpr double kBarWidth = 16.0;
constexpr double kGroupGap = 22.0;
constexpr double kLeft = 64.0, kRight = 24.0, kTop = 70.0, kPlotHeight = 260.0;
constexpr double kCharWidth = 6.2;     // average width of an 11px sans-serif character
constexpr double kSmallCharWidth = 5.6;  // the same at 10px (sub-labels)

std::string number(double value, int decimals = 1) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string xml(const std::string& text) {
  std::string out;
  for (char c : singleLineText(text)) {  // XML allows no control characters
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// A round step giving about five grid lines up to `top`.
double gridStep(double top) {
  const double raw = top / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (factor * magnitude >= raw) return factor * magnitude;
  return 10.0 * magnitude;
}

std::vector<double> methodValues(const MethodScores& s) {
  return {s.projection_mean, s.projection_max, s.labeloctomap};
}

BarChart methodChart(std::string title) {
  BarChart chart;
  chart.title = std::move(title);
  chart.y_label = "IU_3d x100";
  chart.series = {"Projection (Mean)", "Projection (Max)", "LabelOctoMap"};
  return chart;
}

}  // namespace

std::string barChartSvg(const BarChart& chart) {
  const size_t series = std::max<size_t>(1, chart.series.size());
  const double group_width = static_cast<double>(series) * kBarWidth + kGroupGap;
  const double plot_width = std::max(360.0, group_width * static_cast<double>(chart.groups.size()));
  size_t longest_sublabel = 0;
  for (const auto& g : chart.groups) longest_sublabel = std::max(longest_sublabel, g.sublabel.size());
  // Sub-labels are slanted by 40 degrees; their vertical reach is length * sin(40).
  const double bottom = 30.0 + std::min(220.0, kSmallCharWidth * static_cast<double>(longest_sublabel) * 0.643) + 8.0;
  // A slanted sub-label reaches left of its group by length * cos(40): the
  // plot moves right far enough that the first groups' long names stay in
  // the picture.
  double left = kLeft;
  for (size_t g = 0; g < chart.groups.size(); ++g) {
    const double center = group_width * static_cast<double>(g) + kGroupGap / 2 +
                          kBarWidth * static_cast<double>(series) / 2 + 4;
    const double reach =
        kSmallCharWidth * static_cast<double>(chart.groups[g].sublabel.size()) * 0.766;
    left = std::max(left, reach - center + 6);
  }
  const double width = left + plot_width + kRight;
  const double height = kTop + kPlotHeight + bottom;

  double top_value = 0.0;
  for (const auto& g : chart.groups)
    for (double v : g.values)
      if (std::isfinite(v)) top_value = std::max(top_value, v * chart.y_unit);
  if (!(top_value > 0.0)) top_value = 1.0;
  const double step = gridStep(top_value);
  const double axis_top = std::ceil(top_value / step - 1e-9) * step;
  const int decimals = step < 1.0 ? 2 : (step < 10.0 && std::floor(step) != step ? 1 : 0);
  auto y_of = [&](double v) { return kTop + kPlotHeight * (1.0 - std::clamp(v / axis_top, 0.0, 1.0)); };

  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << number(width, 0) << "\" height=\""
      << number(height, 0) << "\" viewBox=\"0 0 " << number(width, 0) << " " << number(height, 0)
      << "\" font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"11\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << number(width / 2, 1) << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" "
      << "font-weight=\"bold\">" << xml(chart.title) << "</text>\n";

  // Legend, one swatch per series, centred under the title.
  double legend_width = 0.0;
  for (const auto& name : chart.series) legend_width += 22.0 + kCharWidth * static_cast<double>(name.size()) + 18.0;
  double x = std::max(left, width / 2 - legend_width / 2);
  for (size_t s = 0; s < chart.series.size(); ++s) {
    svg << "<rect x=\"" << number(x, 1) << "\" y=\"36\" width=\"14\" height=\"14\" fill=\""
        << kPalette[s % std::size(kPalette)] << "\"/>\n"
        << "<text x=\"" << number(x + 20, 1) << "\" y=\"47\">" << xml(chart.series[s]) << "</text>\n";
    x += 22.0 + kCharWidth * static_cast<double>(chart.series[s].size()) + 18.0;
  }

  // Grid and y axis.
  for (double v = 0.0; v <= axis_top + step * 1e-6; v += step) {
    const double y = y_of(v);
    svg << "<line x1=\"" << left << "\" y1=\"" << number(y, 1) << "\" x2=\""
        << number(left + plot_width, 1) << "\" y2=\"" << number(y, 1) << "\" stroke=\""
        << (v == 0.0 ? "#000" : "#ddd") << "\"/>\n"
        << "<text x=\"" << left - 6 << "\" y=\"" << number(y + 4, 1) << "\" text-anchor=\"end\">"
        << number(v, decimals) << "</text>\n";
  }
  svg << "<line x1=\"" << left << "\" y1=\"" << kTop << "\" x2=\"" << left << "\" y2=\""
      << kTop + kPlotHeight << "\" stroke=\"#000\"/>\n"
      << "<text transform=\"translate(18," << number(kTop + kPlotHeight / 2, 1)
      << ") rotate(-90)\" text-anchor=\"middle\">" << xml(chart.y_label) << "</text>\n";

  // Bars, with the exact value as a tooltip.
  for (size_t g = 0; g < chart.groups.size(); ++g) {
    const auto& group = chart.groups[g];
    const double group_x = left + group_width * static_cast<double>(g) + kGroupGap / 2;
    for (size_t s = 0; s < group.values.size() && s < series; ++s) {
      const double value = std::isfinite(group.values[s]) ? group.values[s] * chart.y_unit : 0.0;
      const double y = y_of(value);
      svg << "<rect x=\"" << number(group_x + kBarWidth * static_cast<double>(s), 1) << "\" y=\"" << number(y, 1)
          << "\" width=\"" << kBarWidth - 1 << "\" height=\"" << number(kTop + kPlotHeight - y, 1) << "\" fill=\""
          << kPalette[s % std::size(kPalette)] << "\"><title>" << xml(group.label)
          << (s < chart.series.size() ? " " + xml(chart.series[s]) : std::string()) << ": " << number(value, 2)
          << "</title></rect>\n";
    }
    const double center = group_x + kBarWidth * static_cast<double>(series) / 2;
    const double label_y = kTop + kPlotHeight + 16;
    svg << "<text x=\"" << number(center, 1) << "\" y=\"" << number(label_y, 1) << "\" text-anchor=\"middle\">"
        << xml(group.label) << "</text>\n";
    if (!group.sublabel.empty())
      svg << "<text transform=\"translate(" << number(center + 4, 1) << "," << number(label_y + 12, 1)
          << ") rotate(-40)\" text-anchor=\"end\" font-size=\"10\" fill=\"#444\">" << xml(group.sublabel)
          << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string reportSvg(const EvaluationReport& report) {
  BarChart chart = methodChart("IU_3d per object: " + report.sequence);
  for (const auto& o : report.objects)
    chart.groups.push_back({std::to_string(o.label), o.name, methodValues(o.iou_3d)});
  chart.groups.push_back({"mean", std::to_string(report.summary.objects) + " objects",
                          methodValues(report.summary.iou_3d)});
  return barChartSvg(chart);
}

std::string aggregateSvg(const std::vector<EvaluationReport>& reports) {
  BarChart chart = methodChart("Mean IU_3d per sequence");
  // Sequence names are long: they go slanted under a running number.
  for (size_t i = 0; i < reports.size(); ++i)
    chart.groups.push_back({std::to_string(i + 1), reports[i].sequence, methodValues(reports[i].summary.iou_3d)});
  const ScoreSummary all = summarizeAll(reports);
  chart.groups.push_back({"all", std::to_string(all.objects) + " objects", methodValues(all.iou_3d)});
  return barChartSvg(chart);
}

}  // namespace lom
