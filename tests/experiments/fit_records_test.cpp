// The records of one fit as every leg's identify processes them (fit_records.hpp): each in the band
// chosen from it by the robot asked for, the choices under its file in the JSON, errors naming it.
#include "exoid/experiments/protocol/fit_records.hpp"

#include "../support/closed_loop_multisine.hpp"
#include "exoid/experiments/protocol/options.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace exoid::experiments {
namespace {

// Four seconds of the default leg tracking its multisine, with a little encoder and torque noise.
ident::Dataset multisine(std::uint64_t seed) {
  const test::ClosedLoopMultisine m = test::closedLoopMultisine(4000, test::rigController(false));
  return test::measuredMultisine(m, {1e-4, 0.05, seed}, false);
}

std::string errorOf(const std::vector<std::string>& files, const std::vector<ident::Dataset>& data) {
  try {
    testing::internal::CaptureStdout();
    processFitRecords(files, data, ident::twoLinkLeg(test::kMultisineConstants), defaultIdentifySignals());
  } catch (const std::invalid_argument& e) {
    testing::internal::GetCapturedStdout();
    return e.what();
  }
  testing::internal::GetCapturedStdout();
  return "";
}

// Each record is processed as it would be alone: its own band, by the band robot when one is
// given (the APAL leg's X without the knee armature it fits), into the fitted robot's rows.
TEST(FitRecords, EachRecordIsProcessedAsAloneInTheBandTheBandRobotChooses) {
  const ident::Robot fitted = ident::twoLinkLeg(test::kMultisineConstants, true), leg = ident::twoLinkLeg(test::kMultisineConstants);
  const std::vector<ident::Dataset> data = {multisine(1), multisine(2).window(0, 3000)};
  const ident::SignalOptions given = defaultIdentifySignals();
  testing::internal::CaptureStdout();
  const FitRecords fit = processFitRecords({"a.csv", "b.csv"}, data, fitted, given, {}, &leg);
  const std::string printed = testing::internal::GetCapturedStdout();
  ASSERT_EQ(fit.rows.size(), 2u);
  for (std::size_t r = 0; r < 2; ++r) {
    const std::string file = r == 0 ? "a.csv" : "b.csv";
    std::optional<ident::BandChoice> band;
    const ident::SignalOptions alone = ident::resolveSignalOptions(data[r], leg, given, {}, &band);
    ASSERT_TRUE(band && fit.bands[r]) << file;  // the default chooses the band from the record
    EXPECT_EQ(fit.signals[r].cutoff_hz, alone.cutoff_hz) << file;
    EXPECT_EQ(fit.signals[r].derivative_cutoff_hz, alone.derivative_cutoff_hz) << file;
    const ident::RecordRows rows = ident::processRecord(data[r], fitted, alone);
    ASSERT_EQ(fit.rows[r].W.cols(), 11) << file;  // the fitted robot's columns (X and Ia2)
    EXPECT_EQ(fit.rows[r].W, rows.W) << file;
    EXPECT_EQ(fit.rows[r].y, rows.y) << file;
    EXPECT_NE(printed.find(file + ": band: "), std::string::npos) << printed;
    const nlohmann::json& j = fit.json.at(file);
    EXPECT_EQ(j.at("cutoff_hz").get<double>(), alone.cutoff_hz) << file;
    EXPECT_TRUE(j.at("chosen_from_data").get<bool>()) << file;
    EXPECT_EQ(j.at("reason").get<std::string>(), band->describe()) << file;
    EXPECT_EQ(j.at("samples").get<Eigen::Index>(), data[r].size()) << file;
    EXPECT_EQ(j.at("rows").get<Eigen::Index>(), rows.y.size()) << file;
  }
  // A validation record is processed in the first record's band.
  EXPECT_EQ(fit.validationSignals(given).cutoff_hz, fit.signals[0].cutoff_hz);
}

TEST(FitRecords, ARecordThatCannotBeProcessedIsNamed) {
  const std::string short_record = errorOf({"long.csv", "short.csv"}, {multisine(1), multisine(1).window(0, 50)});
  EXPECT_EQ(short_record.rfind("short.csv: record too short to choose a band", 0), 0u) << short_record;
  EXPECT_NE(errorOf({}, {}).find("at least one"), std::string::npos);
}

}  // namespace
}  // namespace exoid::experiments
