#pragma once
// Command-line flags shared by the identification commands (identify, identifiability,
// reproduce, sweep), and their JSON echo for outputs.
#include "exoid/core/tree_selection.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/signals/base_terms.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exoid::experiments {

/// --diff, --no-filter, --cutoff-hz, --filter-order, --no-filter-torque, --differentiate.
/// The signal processing `identify` and `identifiability` use by default: the parallel filtering
/// (exact on exact data whatever the filter) with the pedestal's base-motion terms when the
/// dataset has the IMU columns; the paper's is `--processing paper`.
ident::SignalOptions defaultIdentifySignals();
/// For --seed and --master-seed: a non-negative integer that fits 64 bits (CLI11 alone would
/// wrap -1 to 2^64 - 1 silently).
const CLI::Validator& seedValidator();
/// A number > 0 (CLI11's PositiveNumber names the range as 309-digit numbers).
const CLI::Validator& positiveNumber();
/// --base LINK, --tip LINK and --lock JOINT=VALUE (repeatable): the chain of a tree that the
/// command reads from --model (core::ChainSelection), the same spelling in every command.
/// Without `with_lock` the command declares --lock itself and passes its JOINT=VALUE entries on
/// with addTreeLock (simulate: a JOINT alone is its rig's lock).
void addChainSelectionOptions(CLI::App& cmd, core::ChainSelection& selection, bool with_lock = true);
/// selection.addLock(joint_equals_value), refused naming --lock.
void addTreeLock(core::ChainSelection& selection, const std::string& joint_equals_value);
void addSignalOptions(CLI::App& app, ident::SignalOptions& o);
/// --seed, PSO, RLS, range and cost flags.
void addMethodOptions(CLI::App& app, ident::MethodOptions& o);

/// One spelling of the options that differ by leg, for every leg: --stage JOINT=FILE (the record's
/// first moving joint, the joints above it locked) and --armature JOINT,... The APAL leg reads
/// them as its own: a knee stage is --knee-data; --armature knee (or all) is its knee armature Ia2
/// (a hip rotor's inertia adds to Jt alone, which the model fits already). Throw
/// CLI::ValidationError naming the option and what was expected.
std::pair<std::string, std::string> parseStage(const std::string& joint_equals_file);
bool apalKneeArmature(const std::vector<std::string>& armature);

/// Leg constants from flags, else from the dataset's "# thigh_length_m:" / "# gravity_mps2:"
/// metadata, else the defaults (0.45 m, 9.81 m/s^2). `origin` says which, for the output.
struct ConstantsFlags {
  std::optional<double> thigh_length_m;
  std::optional<double> gravity_mps2;
};
void addConstantsOptions(CLI::App& app, ConstantsFlags& f);
/// Lt and g: the flag, else the log profile's [model], else the dataset's metadata. Lt has no
/// default (it scales every thigh parameter): without it, throws std::invalid_argument saying
/// how to give it. g defaults to 9.81 m/s^2, said in `origin`.
ident::LegConstants resolveConstants(const ConstantsFlags& f, const ident::Dataset& d, std::string* origin,
                                     std::optional<double> profile_thigh_length_m = std::nullopt,
                                     std::optional<double> profile_gravity_mps2 = std::nullopt);

nlohmann::json toJson(const ident::SignalOptions& o);
nlohmann::json toJson(const ident::MethodOptions& o);
/// --base-terms' (and a sweep's base_terms') words: off, auto, on, judged.
const std::map<std::string, ident::BaseTerms>& baseTermsChoices();
/// A record's base-motion terms' choice, as identify prints it.
std::string baseTermsNote(const ident::BaseTermsChoice& c);
/// The line saying that records judged differently share one (ident::shareBaseTerms).
std::string sharedBaseTermsNote(const ident::BaseTermsChoice& pooled);
/// The base-motion terms' choice from a record (ident::chooseBaseTerms): kept, its numbers, the rule.
nlohmann::json toJson(const ident::BaseTermsChoice& c);
/// True when a record processed with `signals` carries base-motion terms (its IMU columns, and
/// base_terms on, or auto: resolved, or unjudged).
bool usesBaseMotion(const ident::Dataset& d, const ident::SignalOptions& signals);

}  // namespace exoid::experiments
