// The log reader and the processing behind `exoid identify`, on arbitrary bytes: either a
// DatasetError / std::invalid_argument naming the problem, or a dataset whose invariants hold
// (uniform increasing time, finite bounded values, consistent sizes) and rows a method can fit.
#include "fuzz_support.hpp"

#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <cmath>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace exoid::ident;
  if (size < 1) return 0;
  // The first byte picks the reading options (bits 0-2), the processing (3-4) and how the rows
  // are cut into ranges (5-7); the rest is the file.
  CsvReadOptions o;
  o.sampling = (data[0] & 1) ? SamplingMode::kStrict : SamplingMode::kResample;
  if (data[0] & 2) o.format.time_scale_s = 1e-3;
  if (data[0] & 4) o.format.angle_scale_rad = M_PI / 180.0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  // Read whole, and cut into ranges of a few bytes (on two threads when bit 5 is set): the same
  // dataset, or the same error (the first in the file), either way.
  const auto read = [&](std::size_t range_bytes, int threads, std::string& error) {
    CsvReadOptions ranged = o;
    ranged.range_bytes = range_bytes;
    ranged.threads = threads;
    try {
      return parseDatasetText(text, "fuzz.csv", ranged);
    } catch (const DatasetError& e) {
      error = e.what();
    } catch (const std::invalid_argument& e) {
      error = e.what();
    }
    return Dataset{};
  };
  std::string error, ranged_error;
  const Dataset d = read(text.size() + 1, 1, error);
  const Dataset in_ranges = read(1 + 5 * static_cast<std::size_t>(data[0] >> 6), (data[0] & 32) ? 2 : 1, ranged_error);
  EXOID_FUZZ_CHECK(error == ranged_error);
  const auto same = [](const auto& a, const auto& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && (a.size() == 0 || a == b);
  };
  EXOID_FUZZ_CHECK(same(d.t_s, in_ranges.t_s) && same(d.q_rad, in_ranges.q_rad) && same(d.tau_Nm, in_ranges.tau_Nm) && same(d.extra, in_ranges.extra) &&
                   d.comments == in_ranges.comments && d.extra_names == in_ranges.extra_names && d.text_columns == in_ranges.text_columns &&
                   d.qd_radps.has_value() == in_ranges.qd_radps.has_value() &&
                   (!d.qd_radps || same(*d.qd_radps, *in_ranges.qd_radps)) &&
                   d.qdd_radps2.has_value() == in_ranges.qdd_radps2.has_value() &&
                   (!d.qdd_radps2 || same(*d.qdd_radps2, *in_ranges.qdd_radps2)) &&
                   d.sampling.rows_read == in_ranges.sampling.rows_read &&
                   d.sampling.intervals_off == in_ranges.sampling.intervals_off &&
                   d.sampling.resampled == in_ranges.sampling.resampled &&
                   d.sampling.max_dt_line == in_ranges.sampling.max_dt_line);
  if (!error.empty()) return 0;
  const Eigen::Index n = d.size();
  EXOID_FUZZ_CHECK(n >= o.min_rows && d.q_rad.rows() == n && d.tau_Nm.rows() == n && d.extra.rows() == n);
  EXOID_FUZZ_CHECK(d.t_s.allFinite() && d.q_rad.allFinite() && d.tau_Nm.allFinite() && d.extra.allFinite());
  for (Eigen::Index i = 1; i < n; ++i) EXOID_FUZZ_CHECK(d.t_s[i] > d.t_s[i - 1]);
  if (!(data[0] & 8)) return 0;
  // And the parallel processing of what was read: `exoid identify`'s default, the band chosen from
  // the record (its spectrum, a pilot fit and the consistency scan), or a fixed 10 Hz band.
  SignalOptions s;
  s.processing = Processing::kParallel;
  s.differentiation = Differentiation::kCentral4;
  s.cutoff_from_data = s.derivative_cutoff_from_data = (data[0] & 16) != 0;
  try {
    const RecordRows r = processRecord(d, twoLinkLeg(LegConstants{0.45, 9.81}), s);
    EXOID_FUZZ_CHECK(r.W.allFinite() && r.y.allFinite() && r.W.rows() == r.y.size());
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
