#include "exoid/ident/model/chain_band_iv.hpp"

#include "exoid/ident/model/chain_processing.hpp"
#include "exoid/ident/signals/band.hpp"

#include <optional>
#include <stdexcept>

namespace exoid::ident {

BandIvRows chainBandIvRows(const Dataset& d, const ChainModel& model, const BaseParameters& base, const SignalOptions& o,
                           double instrument_cutoff_hz) {
  // The same record with every angle (and recorded derivative) low-passed at the motion's band,
  // processed in the band chosen on the record itself (so rows and instruments align).
  const Dataset smooth = instrumentRecord(d, o, instrument_cutoff_hz);
  std::optional<BandChoice> band;
  const ChainRecord measured = processChainRecord(d, model, o, &band);
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
