// Bad input gets a message about the input and what would be accepted, a non-zero exit, and no
// output: physical bounds on simulation settings and log values, other separators, time units,
// short records, 309-digit ranges.
#include "cli_test_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace exoid {
namespace {

namespace fs = std::filesystem;

std::string scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("exoid_input_errors_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return (d / name).string();
}

struct Outcome {
  int rc;
  std::string text;
};

Outcome run(const std::vector<std::string>& args) {
  std::ostringstream buffer;
  std::streambuf* old_out = std::cout.rdbuf(buffer.rdbuf());
  std::streambuf* old_err = std::cerr.rdbuf(buffer.rdbuf());
  const int rc = test::runExoid(args);
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  return {rc, buffer.str()};
}

// A valid 2 s log at 1 kHz, with a callback to spoil it.
std::string writeLog(const std::string& name, const std::string& header, char sep, double dt, double tau_scale = 1.0) {
  std::ostringstream out;
  out << header << '\n';
  for (int i = 0; i < 2000; ++i) {
    const double t = i * dt, s = std::sin(2 * M_PI * 1.0 * i * 1e-3);
    out << t << sep << 0.3 * s << sep << 0.5 + 0.4 * s << sep << 20 * s * tau_scale << sep << 3 * s << '\n';
  }
  const std::string p = scratch(name);
  std::ofstream(p) << out.str();
  return p;
}

TEST(InputErrors, SimulationSettingsAreBoundedToPhysicalRanges) {
  const std::string out = scratch("sim.csv");
  Outcome o = run({"simulate", "--noise-tau", "1e308", "--out", out});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("'noise_tau_Nm' must be in [0, 1000] N m"), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(out));
  o = run({"simulate", "--ramp", "1e7", "--out", out});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("'ramp_s' must be in [0, 600] s"), std::string::npos) << o.text;
  o = run({"simulate", "--duration", "0", "--out", out});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("must be > 0 and finite, got 0"), std::string::npos) << o.text;
  EXPECT_LT(o.text.size(), 300u) << "a range printed in full: " << o.text;
}

TEST(InputErrors, ALogValueBeyondAnyLegIsRefusedAtItsCell) {
  const std::string log = writeLog("huge.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-3, 1e306);
  const Outcome o = run({"identify", "--data", log, "--thigh-length", "0.45"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("huge.csv:"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("is not a physical value (|tau_hip| <= 1e+06 in the log's units)"), std::string::npos) << o.text;
}

TEST(InputErrors, OtherSeparatorsAreNamedAndAByteOrderMarkIsAccepted) {
  Outcome o = run({"identify", "--data", writeLog("tabs.csv", "t\tq_hip\tq_knee\ttau_hip\ttau_knee", '\t', 1e-3), "--thigh-length", "0.45"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("separated by tabs: exoid reads comma-separated files"), std::string::npos) << o.text;
  o = run({"identify", "--data", writeLog("semi.csv", "t;q_hip;q_knee;tau_hip;tau_knee", ';', 1e-3), "--thigh-length", "0.45"});
  EXPECT_NE(o.text.find("separated by semicolons"), std::string::npos) << o.text;
  o = run({"identify", "--data", writeLog("bom.csv", "\xEF\xBB\xBFt,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-3), "--thigh-length", "0.45"});
  EXPECT_EQ(o.text.find("missing required column"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("condition"), std::string::npos) << o.text;  // it identified
}

TEST(InputErrors, TimeInTheWrongUnitIsSuggested) {
  // Milliseconds read as seconds: a 1 Hz log, too slow for a band chosen from the data, and below
  // a given 10 Hz filter's Nyquist rate.
  Outcome o = run({"identify", "--data", writeLog("ms.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1.0), "--thigh-length", "0.45"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("the record is sampled at 1 Hz: too slow to resolve a motion"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("--time-unit ms"), std::string::npos) << o.text;
  o = run({"identify", "--data", writeLog("ms.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1.0), "--thigh-length", "0.45",
           "--cutoff-hz", "10"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("'cutoff_hz' = 10 Hz must be below the record's Nyquist frequency, 0.5 Hz"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("--time-unit ms"), std::string::npos) << o.text;
  o = run({"identify", "--data", writeLog("tiny_dt.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-300), "--thigh-length", "0.45"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("is its time column in another unit"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("pole"), std::string::npos) << o.text;
}

TEST(InputErrors, AnglesInDegreesReadAsRadiansAreNamedWithTheLikelyUnit) {
  // The new user's log: 17 deg of hip and 23 deg of knee amplitude, read as radians (no unit said).
  std::ostringstream out;
  out << "t,q_hip,q_knee,tau_hip,tau_knee\n";
  for (int i = 0; i < 4000; ++i) {
    const double s = std::sin(2 * M_PI * 1.0 * i * 1e-3);
    out << i * 1e-3 << ',' << 0.3 * s * 180.0 / M_PI << ',' << (0.5 + 0.4 * s) * 180.0 / M_PI << ',' << 20 * s << ',' << 3 * s << '\n';
  }
  const std::string p = scratch("degrees.csv");
  std::ofstream(p) << out.str();
  Outcome o = run({"identify", "--data", p, "--thigh-length", "0.45"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("q_hip spans 34.38 rad"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("--angle-unit deg"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("friction"), std::string::npos) << o.text;
  o = run({"identifiability", "--data", p, "--thigh-length", "0.45"});
  EXPECT_NE(o.text.find("--angle-unit deg"), std::string::npos) << o.text;
  // Said in degrees: read, converted, identified; said in radians: trusted (no refusal for the unit).
  o = run({"identify", "--data", p, "--thigh-length", "0.45", "--angle-unit", "deg", "--method", "ls"});
  EXPECT_EQ(o.text.find("--angle-unit deg"), std::string::npos) << o.text;
  o = run({"identify", "--data", p, "--thigh-length", "0.45", "--angle-unit", "rad", "--method", "ls"});
  EXPECT_EQ(o.text.find("implausible in radians"), std::string::npos) << o.text;
}

TEST(InputErrors, AWrongColumnMapNamesTheFilesOwnHeaderAndUnknownExoidNames) {
  const std::string p = writeLog("own_names.csv", "time,pos1,pos2,trq1,trq2", ',', 1e-3);
  // A log name that is not there: the file's own header is listed, not the half-renamed one.
  Outcome o = run({"identify", "--data", p, "--thigh-length", "0.45", "--columns", "t=time,q_hip=pos1,q_knee=pos3,tau_hip=trq1,tau_knee=trq2"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("column 'pos3' (mapped to q_knee) is not in the header; it has: time, pos1, pos2, trq1, trq2"), std::string::npos) << o.text;
  // An exoid-side name exoid does not read: named as unknown, with the map's direction.
  o = run({"identify", "--data", p, "--thigh-length", "0.45", "--columns", "time=time,q_hip=pos1,q_knee=pos2,tau_hip=trq1,tau_knee=trq2"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("unknown exoid column 'time'"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("e.g. t=time"), std::string::npos) << o.text;
  o = run({"identify", "--data", p, "--thigh-length", "0.45", "--method", "ls", "--columns", "t=time,q_hip=pos1,q_knee=pos2,tau_hip=trq1,tau_knee=trq2"});
  EXPECT_EQ(o.text.find("unknown exoid column"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("is not in the header"), std::string::npos) << o.text;
}

TEST(InputErrors, AutoCutoffsAreIdentifysNotTheProtocols) {
  // The protocol's arms and render's prediction use fixed cutoffs; 'auto' there would be silently
  // ignored or mismatch the arms' noise paths, so it is refused by name.
  const Outcome o = run({"reproduce", "--cutoff-hz", "auto", "--out", scratch("auto_reproduce"), "--no-plots", "--no-optimised-arm"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("not auto"), std::string::npos) << o.text;
}

TEST(InputErrors, ARecordTooShortForTheProcessingSaysHowLongItMustBe) {
  const std::string out = scratch("short_reproduce");
  const Outcome o = run({"reproduce", "--duration", "0.002", "--out", out, "--no-plots", "--no-optimised-arm"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("record too short: 2 samples, and the processing trims 300 at each end"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("least squares: need at least as many rows"), std::string::npos) << o.text;
}

}  // namespace
}  // namespace exoid

namespace exoid {
namespace {

TEST(CommandLineMessages, HelpIsPlainWordsWithinOneHundredColumns) {
  // No CLI11 internals, no line past 100 characters, defaults that say what identify does.
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"--help"}, {"identify", "--help"}, {"identifiability", "--help"}, {"sweep", "--help"}, {"reproduce", "--help"},
           {"simulate", "--help"}, {"excite", "--help"}}) {
    const Outcome o = run(args);
    for (const char* internal : {"ENUM:", "value in {", "{false}", "{true}", "{1,0,2}", "TEXT:"}) {
      EXPECT_EQ(o.text.find(internal), std::string::npos) << args.front() << " shows '" << internal << "'";
    }
    std::istringstream lines(o.text);
    std::string line;
    while (std::getline(lines, line)) {
      EXPECT_LE(line.size(), 100u) << args.front() << ": " << line;
      // A default that is where this build put a file differs between machines and can run past the width.
      EXPECT_EQ(line.find("(default /"), std::string::npos) << args.front() << ": " << line;
    }
  }
  const Outcome id = run({"identify", "--help"});
  EXPECT_NE(id.text.find("--processing paper|parallel (default parallel)"), std::string::npos) << id.text;
  EXPECT_NE(id.text.find("(default 10 x the largest |LS estimate|)"), std::string::npos) << id.text;
  EXPECT_NE(id.text.find("--no-filter "), std::string::npos) << id.text;
  const Outcome rep = run({"reproduce", "--help"});
  EXPECT_NE(rep.text.find("(default the shipped configs/excitation_knee.json)"), std::string::npos) << rep.text;
  // exoid --help names every arm reproduce runs.
  const Outcome top = run({"--help"});
  for (const char* arm : {"ls-exact", "ls-stacked", "ls-parallel", "idim-iv-base", "default"}) {
    EXPECT_NE(top.text.find(arm), std::string::npos) << arm;
  }
}

TEST(CommandLineMessages, TheReadmesNameForTheDefaultIsAMethod) {
  const std::string log = writeLog("ls_parallel.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-3);
  Outcome o = run({"identify", "--data", log, "--thigh-length", "0.45", "--method", "ls-parallel"});
  EXPECT_EQ(o.text.find("unknown method"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("ls"), std::string::npos);
  o = run({"identify", "--data", log, "--thigh-length", "0.45", "--method", "ls-parallel", "--processing", "paper"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("contradicts"), std::string::npos) << o.text;
  o = run({"identify", "--data", log, "--thigh-length", "0.45", "--method", "ls-exact"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("is an arm of exoid reproduce and exoid sweep"), std::string::npos) << o.text;
}

TEST(CommandLineMessages, AnUnknownCommandIsNamedWithTheNearestAndTheList) {
  Outcome o = run({"frobnicate"});
  EXPECT_EQ(o.rc, 2);
  EXPECT_NE(o.text.find("unknown command 'frobnicate'"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("commands: identify, identifiability"), std::string::npos) << o.text;
  o = run({"simulat", "--out", "x.csv"});
  EXPECT_NE(o.text.find("did you mean 'simulate'?"), std::string::npos) << o.text;
}

// --model names a robot in every command, a URDF as well as an MJCF; --urdf is its alias.
TEST(CommandLineMessages, TruthTakesAUrdfByModelAsEveryCommandDoes) {
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/apal_leg.urdf";
  const Outcome by_model = run({"truth", "--model", urdf});
  const Outcome by_urdf = run({"truth", "--urdf", urdf});
  EXPECT_EQ(by_model.rc, 0) << by_model.text;
  EXPECT_NE(by_model.text.find("X of the rigid links of"), std::string::npos) << by_model.text;
  EXPECT_EQ(by_model.text, by_urdf.text);
  const Outcome both = run({"truth", "--model", urdf, "--urdf", urdf});
  EXPECT_NE(both.rc, 0);
  EXPECT_NE(both.text.find("not both"), std::string::npos) << both.text;
}

TEST(CommandLineMessages, AnUnknownMethodListsAllToo) {
  const std::string log = writeLog("m.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-3);
  const Outcome o = run({"identify", "--data", log, "--thigh-length", "0.45", "--method", "foo"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("unknown method 'foo'"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("all = every method but idim-iv"), std::string::npos) << o.text;
}

TEST(CommandLineMessages, OutputPathsAreCheckedBeforeTheWork) {
  const std::string log = writeLog("j.csv", "t,q_hip,q_knee,tau_hip,tau_knee", ',', 1e-3);
  Outcome o = run({"identify", "--data", log, "--thigh-length", "0.45", "--json", "/nonexistent-exoid/out.json"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("folder '/nonexistent-exoid' does not exist"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("condition number"), std::string::npos) << "it identified first: " << o.text;
  o = run({"simulate", "--out", "/nonexistent-exoid/x.csv"});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("folder '/nonexistent-exoid' does not exist"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("tracking error"), std::string::npos) << "it simulated first: " << o.text;
  // Commands that write a folder: made (or refused, naming why) before the work.
  const std::string file = scratch("a-file");
  std::ofstream(file) << "x";
  o = run({"reproduce", "--out", file + "/out", "--no-video"});
  EXPECT_EQ(o.rc, 1);
  EXPECT_NE(o.text.find("cannot use '" + file + "/out' as the output folder: Not a directory"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("simulating"), std::string::npos) << "it simulated first: " << o.text;
  o = run({"sweep", "--out", file + "/sweep", "--seeds", "1", "--methods", "ls", "--noise-tau", "0", "--vibration", "0"});
  EXPECT_EQ(o.rc, 1);
  EXPECT_NE(o.text.find("cannot use '" + file + "/sweep/runs' as the output folder: Not a directory"), std::string::npos) << o.text;
  o = run({"excite", "--out", file + "/design.json"});
  EXPECT_EQ(o.rc, 1);
  EXPECT_NE(o.text.find("cannot use '" + file + "' as the output folder: it is a file"), std::string::npos) << o.text;
}

TEST(CommandLineMessages, AnOddVideoSizeIsRefusedBeforeSimulating) {
  const Outcome o = run({"render", "--width", "641", "--out", scratch("odd.mp4")});
  EXPECT_NE(o.rc, 0);
  EXPECT_NE(o.text.find("needs an even width and height (yuv420p), got 641x"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("simulated"), std::string::npos) << "it simulated first: " << o.text;
}

}  // namespace
}  // namespace exoid
