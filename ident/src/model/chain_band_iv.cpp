#include "exoid/ident/model/chain_band_iv.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/model/chain_processing.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <optional>
#include <stdexcept>

namespace exoid::ident {

BandIvRows chainBandIvRows(const Dataset& d, const ChainModel& model, const BaseParameters& base, const SignalOptions& o,
                           double instrument_cutoff_hz) {
  if (o.processing != Processing::kParallel) {
    throw std::invalid_argument("iv-band needs the parallel processing: its instruments are processed like the rows");
  }
  const double fs = 1.0 / d.sampleInterval_s();
  if (!(instrument_cutoff_hz > 0.0 && instrument_cutoff_hz < 0.5 * fs)) {
    throw std::invalid_argument("iv-band: the instruments' cutoff must be in (0, " + core::formatNumber(0.5 * fs, 6) +
                                ") Hz, got " + core::formatNumber(instrument_cutoff_hz, 6));
  }
  std::optional<BandChoice> band;
  const ChainRecord measured = processChainRecord(d, model, o, &band);
  // The same record with every angle (and recorded derivative) low-passed at the motion's band,
  // processed in the band chosen on the record itself (so rows and instruments align).
  Dataset smooth = d;
  const SosFilter lp = butterworthLowpass(4, instrument_cutoff_hz, fs);
  smooth.q_rad = filtfilt(lp, d.q_rad);
  if (d.qd_radps) smooth.qd_radps = filtfilt(lp, *d.qd_radps);
  if (d.qdd_radps2) smooth.qdd_radps2 = filtfilt(lp, *d.qdd_radps2);
  const ChainRecord instruments = processChainRecord(smooth, model, band ? withBand(o, *band) : o);
  if (instruments.y.size() != measured.y.size()) throw std::logic_error("iv-band: instruments and rows do not align");
  BandIvRows out{base.baseRegressor(measured.W), base.baseRegressor(instruments.W), measured.y};
  const std::vector<JointParameterLayout> layout = model.layout();
  for (int i = 0; i < base.rank; ++i) {
    const int standard = base.independent[static_cast<std::size_t>(i)];
    for (const JointParameterLayout& l : layout) {
      if (l.friction >= 0 && standard == l.friction) out.Z.col(i) = out.H.col(i);  // Coulomb fc
    }
  }
  return out;
}

}  // namespace exoid::ident
