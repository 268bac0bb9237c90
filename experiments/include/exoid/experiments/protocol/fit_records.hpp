#pragma once
// The records of one fit (or of one stage of a segmental strategy) as every leg's identify reads
// them: each processed in the band chosen from it unless the options fix it, the choices printed
// under its file and kept for the JSON.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

struct FitRecords {
  std::vector<ident::SignalOptions> signals;                      ///< each record's options as used (every choice made)
  std::vector<std::optional<ident::BandChoice>> bands;            ///< the band chosen from each record, if any
  std::vector<std::optional<ident::BaseTermsChoice>> base_terms;  ///< each record's base-motion terms' choice, if judged
  std::optional<ident::BaseTermsChoice> shared;  ///< the pooled choice, when the records were judged differently
  std::vector<ident::RecordRows> rows;           ///< each record's rows
  nlohmann::json json = nlohmann::json::object();  ///< by file: its processing as used (identify's processing_per_record)
  /// What a record checked against the fit (--validate) is processed with: `given` in the first
  /// record's band, with its base-motion terms' choice (judged: as made for the fit).
  ident::SignalOptions validationSignals(const ident::SignalOptions& given) const;
};

/// Chooses each record's processing (ident::resolveSignalOptions with `rule`, by `band_robot`, or
/// by `robot` when null), shares the base-motion terms' choice between them, processes each into
/// `robot`'s rows and prints each choice under its file. std::invalid_argument naming the file
/// when a record cannot be processed, and for no record at all. A file given twice is processed
/// twice (its rows stacked twice) and has one entry in the JSON.
FitRecords processFitRecords(const std::vector<std::string>& files, const std::vector<ident::Dataset>& data, const ident::Robot& robot,
                             const ident::SignalOptions& options, const ident::BandRule& rule = {}, const ident::Robot* band_robot = nullptr);

}  // namespace exoid::experiments
