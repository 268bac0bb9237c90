#include "exoid/render/overlay.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace exoid::render {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
constexpr std::array<float, 3> kMeasuredRgb{0.92f, 0.92f, 0.92f};
constexpr std::array<float, 3> kPredictedRgb{0.25f, 0.75f, 1.0f};
constexpr std::array<float, 3> kErrorRgb{1.0f, 0.35f, 0.3f};

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

std::array<double, 2> rangeOf(std::initializer_list<const std::vector<double>*> series) {
  double lo = INFINITY, hi = -INFINITY;
  for (const std::vector<double>* s : series) {
    for (double v : *s) {
      if (std::isnan(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi >= lo)) return {-1.0, 1.0};
  const double margin = std::max(0.08 * (hi - lo), 0.05);  // N m
  return {lo - margin, hi + margin};
}

}  // namespace

void OverlayOptions::validate() const {
  if (!std::isfinite(plot_window_s) || plot_window_s <= 0.0) {
    throw std::invalid_argument("'plot_window_s' must be positive, got " + core::toText(plot_window_s));
  }
  if (max_plot_points < 2 || max_plot_points > 1000) {
    throw std::invalid_argument("'max_plot_points' must be in [2, 1000] (mjMAXLINEPNT), got " +
                                core::toText(max_plot_points));
  }
}

OverlayBuilder::OverlayBuilder(Track track, const OverlayOptions& options) : track_(std::move(track)), options_(options) {
  options_.validate();
  track_.validate();
  y_range_.assign(track_.joints.size(), {0.0, 0.0});
  if (!track_.hasTorque()) return;
  for (std::size_t j = 0; j < track_.joints.size(); ++j) {
    const TrackJoint& jt = track_.joints[j];
    if (track_.hasPrediction()) {
      std::vector<double> err;
      for (std::size_t i = 0; i < track_.t_s.size(); ++i) err.push_back(jt.tau_Nm[i] - jt.tau_pred_Nm[i]);
      y_range_[j] = rangeOf({&jt.tau_Nm, &jt.tau_pred_Nm, &err});
    } else {
      y_range_[j] = rangeOf({&jt.tau_Nm});
    }
  }
}

namespace {

// What a joint's torque line says (measured, or measured/predicted/err), and its value at `row`.
std::string torqueLabel(const Track& tr) {
  return tr.hasPrediction() ? "torque " + tr.torque_name + "/" + tr.prediction_name + "/err" : "torque (" + tr.torque_name + ")";
}

std::string torqueValue(const Track& tr, const TrackJoint& j, std::size_t row) {
  if (!tr.hasPrediction()) return format("%+.2f N m", j.tau_Nm[row]);
  const double meas = j.tau_Nm[row], p = j.tau_pred_Nm[row];
  return std::isnan(p) ? format("%+.2f / n/a (trimmed edge)", meas) : format("%+.2f", meas) + format(" / %+.2f", p) + format(" / %+.2f N m", meas - p);
}

// Each joint's angle and torque: two lines a joint up to three joints; from four, one (two would
// leave the torque panels no room below the text at the default height).
void addJointText(const Track& tr, std::size_t row, std::string& l, std::string& r) {
  const auto angle = [&](const TrackJoint& j) { return format("%+.1f deg", j.q_rad[row] * kRadToDeg); };
  if (tr.joints.size() > 3) {
    l += "\njoint";
    r += "\nangle" + (tr.hasTorque() ? ", " + torqueLabel(tr) : std::string());
    for (const TrackJoint& j : tr.joints) {
      l += "\n" + j.name;
      r += "\n" + angle(j) + (tr.hasTorque() ? ", " + torqueValue(tr, j, row) : std::string());
    }
    return;
  }
  for (const TrackJoint& j : tr.joints) {
    l += "\n" + j.name + " angle";
    r += "\n" + angle(j);
  }
  if (!tr.hasTorque()) return;
  for (const TrackJoint& j : tr.joints) {
    l += "\n" + j.name + " " + torqueLabel(tr);
    r += "\n" + torqueValue(tr, j, row);
  }
}

// The text block at `row`: labels on the left, values on the right.
void addText(const Track& tr, const OverlayOptions& options, std::size_t row, Overlay& o) {
  std::string& l = o.text_left;
  std::string& r = o.text_right;
  l = tr.title.empty() ? std::string(" ") : tr.title;
  r = " ";
  l += "\ntime";
  r += "\n" + format("%.3f s", tr.t_s[row]);
  addJointText(tr, row, l, r);
  if (options.plot && tr.hasTorque()) {
    l += "\nplots";
    r += tr.hasPrediction() ? "\nwhite " + tr.torque_name + ", blue " + tr.prediction_name + ", red err" : "\nwhite " + tr.torque_name;
  }
  if (tr.hasBase()) {
    l += "\npedestal x / z";
    r += "\n" + format("%+.2f", 1e3 * tr.base_x_m[row]) + format(" / %+.2f mm", 1e3 * tr.base_z_m[row]);
  }
}

// The plots' window ending at `row`: its time range and the rows drawn in it.
struct PlotWindow {
  std::array<double, 2> x_range;
  std::vector<std::size_t> rows;
};

PlotWindow plotWindow(const Track& tr, const OverlayOptions& options, std::size_t row) {
  const double dt = (tr.t_s.back() - tr.t_s.front()) / static_cast<double>(tr.t_s.size() - 1);  // as Track::sampleInterval_s
  const double t0 = tr.t_s.front();
  const double t = tr.t_s[row];
  const double w = options.plot_window_s;
  PlotWindow win;
  win.x_range = t - t0 < w ? std::array<double, 2>{t0, t0 + w} : std::array<double, 2>{t - w, t};
  const std::size_t window_rows = static_cast<std::size_t>(std::ceil(w / dt));
  const std::size_t first = row > window_rows ? row - window_rows : 0;
  // Points on a fixed grid of rows (multiples of stride) plus the current row: the decimated
  // curve does not shimmer as the window scrolls.
  const std::size_t stride = std::max<std::size_t>(
      1, (window_rows + static_cast<std::size_t>(options.max_plot_points) - 2) / static_cast<std::size_t>(options.max_plot_points - 1));
  for (std::size_t i = (first + stride - 1) / stride * stride; i < row; i += stride) win.rows.push_back(i);
  win.rows.push_back(row);
  return win;
}

// A joint's torque panel over the window: measured, and with a prediction, predicted and error.
PlotPanel torquePanel(const Track& tr, const TrackJoint& joint, const PlotWindow& win, const std::array<double, 2>& y_range) {
  const std::vector<double>& meas = joint.tau_Nm;
  const std::vector<double>& prd = joint.tau_pred_Nm;
  const bool pred = tr.hasPrediction();
  PlotPanel p;
  p.title = joint.name + " torque (N m)";
  p.x_range = win.x_range;
  p.y_range = y_range;
  PlotLine m{tr.torque_name, kMeasuredRgb, {}, {}};
  PlotLine pl{tr.prediction_name, kPredictedRgb, {}, {}};
  PlotLine e{"error", kErrorRgb, {}, {}};
  for (std::size_t i : win.rows) {
    const auto x = static_cast<float>(tr.t_s[i]);
    m.x.push_back(x);
    m.y.push_back(static_cast<float>(meas[i]));
    if (pred && !std::isnan(prd[i])) {
      pl.x.push_back(x);
      pl.y.push_back(static_cast<float>(prd[i]));
      e.x.push_back(x);
      e.y.push_back(static_cast<float>(meas[i] - prd[i]));
    }
  }
  p.lines.push_back(std::move(m));
  if (pred) {
    p.lines.push_back(std::move(pl));
    p.lines.push_back(std::move(e));
  }
  return p;
}

}  // namespace

Overlay OverlayBuilder::at(std::size_t row) const {
  Overlay o;
  const Track& tr = track_;
  if (row >= tr.t_s.size()) throw std::invalid_argument("overlay row " + core::toText(row) + " >= " + core::toText(tr.t_s.size()));
  if (options_.text) addText(tr, options_, row, o);
  if (options_.plot && tr.hasTorque()) {
    const PlotWindow win = plotWindow(tr, options_, row);
    for (std::size_t j = 0; j < tr.joints.size(); ++j) o.panels.push_back(torquePanel(tr, tr.joints[j], win, y_range_[j]));
  }
  return o;
}

}  // namespace exoid::render
