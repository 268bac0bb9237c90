#pragma once
// The paper's protocol on the simulated leg (paper.md, "Evaluation"): simulate trajectories 1-4,
// process the signals as the paper does, identify with the segmental strategy (knee from 1, hip
// from 3), validate (knee on 2, hip on 4), and score against the truths. `exoid reproduce` runs
// it once and reports; `exoid sweep` runs it over a grid of conditions and seeds.
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/sim/simulate.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

/// Identification variants compared by the protocol.
enum class Variant {
  kLs,         ///< LS, paper signal processing (segmental)
  kRls,        ///< final RLS estimate (segmental)
  kPso,        ///< PSO over the wide box (segmental; the paper's "PSO")
  kRlsPso,     ///< RLS box + PSO (segmental; the paper's method)
  kLad,        ///< exact minimum of the paper's L1 cost (segmental)
  kLsExact,    ///< LS with the exact q, qd, qdd columns and the raw measured torque (segmental)
  kLsStacked,  ///< LS on record 1's knee equation and both of record 3's, all 10 at once
  kLsParallel,  ///< LS, parallel filtering and decimation (Gautier; exoid identify's default), segmental
  kIdimIv,      ///< IDIM-IV on the parallel-processed records, segmental
  kLsBase,      ///< ls-parallel with the pedestal IMU's base-motion terms (ident::BaseMotion)
  kIdimIvBase,  ///< idim-iv with the base-motion terms in the measured rows
  /// exoid identify's defaults (defaultIdentifySignals): parallel processing in the band chosen
  /// from each record (ident::chooseBand), base-motion terms when the IMU columns are there, LS,
  /// segmental like the others, made physically consistent in its reported errors
  /// (applySegmentalConsistency, as identify --knee-data --both-data)
  kDefault,
};
/// "ls", "rls", "pso", "rls-pso", "lad", "ls-exact", "ls-stacked", "ls-parallel", "idim-iv",
/// "ls-base", "idim-iv-base", "default"
const char* toString(Variant v);
Variant parseVariant(const std::string& name);
const std::vector<Variant>& allVariants();

struct ProtocolConfig {
  sim::SimConfig sim;              ///< noise, vibration, cylinder, gains... (trajectory and seed are set per record)
  std::uint64_t seed = 1;          ///< sim seeds and PSO seeds derive from it
  ident::SignalOptions signals;    ///< paper defaults: forward differences, 10 Hz zero-phase filter
  ident::MethodOptions methods;    ///< paper defaults: G = 10000, cost < 1e-2
  ident::IvOptions iv;             ///< IDIM-IV's stopping rule
  /// The 'default' arm's band rule (its constants: a sweep's [identification] band_* keys).
  ident::BandRule band_rule;
  /// The 'default' arm's base-motion terms (a sweep's [identification] base_terms); unset: identify's.
  std::optional<ident::BaseTerms> default_base_terms;
  std::vector<Variant> variants = allVariants();
  /// Designed excitations (exoid excite) replacing the identification records: trajectory 1 (knee
  /// only, the hip locked) and trajectory 3 (both joints). Validation stays on the paper's 2 and 4.
  std::optional<core::FourierSeries> knee_excitation, both_excitation;
  void validate() const;
};

/// The 'default' arm's processing: identify's defaults (defaultIdentifySignals) with the config's
/// base-motion terms, when it sets them.
ident::SignalOptions defaultArmSignals(const ProtocolConfig& c);

/// One simulated record, as the identification sees it.
struct Record {
  int trajectory = 0;
  sim::SimResult sim;
  ident::Dataset data;
  ident::JointSignals processed;  ///< measured signals after the paper's processing
  ident::JointSignals exact_q;    ///< exact q, qd, qdd with the raw measured torque (same trim)
  ident::JointSignals ideal;      ///< exact states with the ideal (vibration-free) torques
  /// The 2-link leg of the record's constants (Lt, g), in the paper's X.
  ident::Robot robot;
  ident::RecordRows processed_rows, exact_rows;  ///< the rows of `processed` and of `exact_q`
  /// Parallel-processed rows (parallelSignals) with the reference and controller of the run;
  /// filled for the identification records (trajectories 1 and 3) only.
  ident::ClosedLoopRecord closed_loop;
  /// The same with the base-motion terms in the measured rows (parallelSignals(.., true)).
  ident::ClosedLoopRecord closed_loop_base;
  /// The default arm's rows and the processing they were made with (the band chosen from this
  /// record); identification records only.
  ident::RecordRows default_rows;
  ident::SignalOptions default_signals;
};

/// The parallel arms' processing: the paper's filter (order, cutoff, edge trim) applied in
/// parallel to the torque and every regressor column, then decimated (ident::Processing::kParallel).
/// With base_terms, the regressor includes the pedestal's motion from the records' IMU columns.
ident::SignalOptions parallelSignals(const ident::SignalOptions& paper, bool base_terms = false);

struct Truths {
  ident::ParamVector rigid;     ///< bare rigid links
  ident::ParamVector best_fit;  ///< segmental LS of the ideal torques at the exact states (1 -> knee, 3 -> hip)
  ident::ParamVector band_min, band_max;  ///< lumped four-bar X(q2): knee block from 1, thigh from 3
  double lt_m = 0.0, g_mps2 = 0.0;
};

struct VariantScore {
  Variant variant = Variant::kLs;
  MethodOutcome outcome;
  ident::TorqueErrorStats knee_validation;  ///< on trajectory 2 (knee equation)
  ident::TorqueErrorStats hip_validation;   ///< on trajectory 4 (hip equation)
  ident::ParamError vs_rigid, vs_best_fit;
  /// ||Y (x - x*)|| / ||Y x*|| per joint on ident::validationStates().
  ident::TorqueSpaceError torque_space_vs_rigid, torque_space_vs_best_fit;
  /// Noise-limited std of each parameter for this variant's regressor, processing and structure
  /// at the records' torque noise (noiseStd): the Cramer-Rao bound the variant is judged by.
  Eigen::VectorXd crb_std;
};

struct ProtocolResult {
  ProtocolConfig config;
  std::array<Record, 4> records;
  Truths truths;
  std::vector<VariantScore> scores;
  double wall_time_s = 0.0;
};

/// Seed of record `trajectory` and of the PSO runs, from the protocol seed (independent streams).
std::uint64_t recordSeed(std::uint64_t seed, int trajectory);
std::uint64_t psoSeed(std::uint64_t seed);

/// Std of each parameter (order of X) that torque noise alone causes in `v`'s estimate: the LS
/// covariance of the regressor the variant fits (processed columns for the paper's processing,
/// exact columns for ls-exact), after its processing of the torque (filtfilt + trim, or trim
/// only), for its structure (segmental with the knee stage's covariance propagated through
/// Eq. 9, or stacked), at sigma_Nm per joint (ident::segmentalNoiseCovariance,
/// ident::lsNoiseCovariance). For LS on raw torque this is the Cramer-Rao bound; every method
/// fitting the same regressor (RLS, PSO, RLS-PSO, LAD) is scored against the same bound.
Eigen::VectorXd noiseStd(Variant v, const std::array<Record, 4>& r, const ident::SignalOptions& signals, double sigma_Nm);

/// Simulates and processes the four records.
std::array<Record, 4> simulateRecords(const ProtocolConfig& c);
Truths truthsOf(const std::array<Record, 4>& r, const ident::LegConstants& lc);
/// Runs every variant on the records. Deterministic for a given config.
ProtocolResult runProtocol(const ProtocolConfig& c);

}  // namespace exoid::experiments
