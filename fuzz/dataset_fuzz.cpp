// The log reader and the processing behind `exoid identify`, on arbitrary bytes: either a
// DatasetError / std::invalid_argument naming the problem, or a dataset whose invariants hold
// (uniform increasing time, finite bounded values, consistent sizes) and rows a method can fit.
#include "fuzz_support.hpp"

#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/leg/regressor.hpp"

#include <cmath>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace exoid::ident;
  if (size < 1) return 0;
  // The first byte picks the reading options, the rest is the file.
  CsvReadOptions o;
  o.sampling = (data[0] & 1) ? SamplingMode::kStrict : SamplingMode::kResample;
  if (data[0] & 2) o.format.time_scale_s = 1e-3;
  if (data[0] & 4) o.format.angle_scale_rad = M_PI / 180.0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  Dataset d;
  try {
    d = parseDatasetText(text, "fuzz.csv", o);
  } catch (const DatasetError&) {
    return 0;
  } catch (const std::invalid_argument&) {
    return 0;
  }
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
    const ProcessedRecord r = processRecord(d, LegConstants{0.45, 9.81}, s);
    EXOID_FUZZ_CHECK(r.hip.allFinite() && r.knee.allFinite() && r.tau_Nm.allFinite());
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
