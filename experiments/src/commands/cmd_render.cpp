// `exoid render`: an offscreen video (H.264 MP4) or a PNG still of the leg, from a simulation
// (the same options as `exoid simulate`) or from a recorded dataset CSV, with an overlay of the
// measured torque and, given an identification JSON, the identified model's prediction and error.
#ifdef EXOID_WITH_RENDER

#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/simulate_request.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/render/clip.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/core/atomic_file.hpp"
#include "exoid/render/video_writer.hpp"
#include "exoid/sim/simulate.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>

namespace exoid::experiments {

namespace {

struct RenderArgs {
  std::string out, data, ident_json;
  // Simulation (as `exoid simulate`).
  sim::SimConfig sim;
  // Rendering.
  render::ClipOptions clip;
  double frame_s = 0.0;
  CLI::Option* frame_opt = nullptr;
  CLI::Option* height_opt = nullptr;
  bool antialias = false;
  bool no_overlay = false, no_plot = false;
  ident::SignalOptions signals;
  core::ChainSelection selection;  ///< a URDF's chain (--base, --tip, --lock JOINT=VALUE)
};

bool endsWithIgnoringCase(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(), [](char a, char b) { return std::tolower(a) == b; });
}

std::string baseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// A model's predicted torques (rows of the prepared signals `s` x joints) placed by time on the
// record `d`'s rows, NaN where the processing trimmed the edges.
void placePrediction(const ident::Dataset& d, const ident::JointSignals& s, const Eigen::MatrixXd& tau, const std::string& name,
                     render::Track& track) {
  const std::size_t n = static_cast<std::size_t>(d.size());
  for (render::TrackJoint& j : track.joints) j.tau_pred_Nm.assign(n, std::numeric_limits<double>::quiet_NaN());
  if (s.size() > 0) {
    const long offset = std::lround((s.t_s[0] - d.t_s[0]) / d.sampleInterval_s());
    for (Eigen::Index i = 0; i < s.size(); ++i) {
      const long row = offset + static_cast<long>(i);
      if (row < 0 || row >= static_cast<long>(n)) continue;
      for (Eigen::Index k = 0; k < tau.cols(); ++k) track.joints[static_cast<std::size_t>(k)].tau_pred_Nm[static_cast<std::size_t>(row)] = tau(i, k);
    }
  }
  track.prediction_name = name;
}

// Any leg's prediction from its parameters theta: the robot's inverse dynamics on the prepared signals.
void addPrediction(const ident::Dataset& d, const ident::SignalOptions& signals, const ident::Robot& robot, const Eigen::VectorXd& theta,
                   const std::string& name, render::Track& track) {
  const ident::JointSignals s = ident::prepareSignals(d, signals);
  placePrediction(d, s, ident::predictTorques(robot, s, theta), name, track);
}

// The APAL leg's identify JSON (`exoid identify --json`): the paper's X and the leg's constants.
void addLegPrediction(const std::string& json_path, const ident::Dataset& d, const ident::SignalOptions& signals, render::Track& track) {
  const nlohmann::json j = readUserJsonFile(json_path, "identification JSON");
  if (!j.is_object() || !j.contains("parameters")) {
    throw std::runtime_error("'" + json_path + "': expected an object with \"parameters\" (as written by `exoid identify --json`)");
  }
  const ident::ParamVector x = paramsFromJson(j.at("parameters"), json_path + ": parameters");
  ident::LegConstants c;
  if (j.contains("constants")) {
    const nlohmann::json& cj = j.at("constants");
    c.thigh_length_m = cj.value("thigh_length_m", c.thigh_length_m);
    c.gravity_mps2 = cj.value("gravity_mps2", c.gravity_mps2);
  }
  c.validate();
  std::string name = j.value("method", std::string("identified"));
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
  addPrediction(d, signals, ident::twoLinkLeg(c), x, name, track);
}

// A chain's identify JSON (`exoid identify --model ... --json`): its least-squares base
// parameters, checked against the model's.
Eigen::VectorXd chainEstimateFrom(const std::string& json_path, const LoadedChain& loaded) {
  const nlohmann::json j = readUserJsonFile(json_path, "identification JSON (--ident)");
  if (!j.is_object() || !j.contains("base_parameters") || !j["base_parameters"].contains("ls") ||
      !j["base_parameters"].contains("names")) {
    throw std::invalid_argument("--ident '" + json_path + "': expected the JSON of `exoid identify --model " + loaded.path +
                                " --json FILE` (base_parameters.names and .ls)");
  }
  std::vector<std::string> names;
  std::vector<double> ls;
  try {
    names = j["base_parameters"]["names"].get<std::vector<std::string>>();
    ls = j["base_parameters"]["ls"].get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument("--ident '" + json_path + "': base_parameters.names must be strings and .ls numbers (" + e.what() + ")");
  }
  // Labels are short: the combinations behind them must match too (another lock posture or geometry).
  const bool same_combinations = !j["base_parameters"].contains("combinations") ||
                                 j["base_parameters"]["combinations"] == nlohmann::json(loaded.base.combinations);
  if (names != loaded.base.names || ls.size() != names.size() || !same_combinations) {
    throw std::invalid_argument("--ident '" + json_path + "': its base parameters are not those of " + loaded.path + " (" +
                                core::toText(loaded.base.rank) + " base parameters; identified with another model or --armature?)");
  }
  return Eigen::Map<const Eigen::VectorXd>(ls.data(), static_cast<Eigen::Index>(ls.size()));
}

// A record's track: every joint's angle and torque, the APAL pedestal's columns when recorded.
render::Track trackOf(const ident::Dataset& d, const std::string& title) {
  render::Track tr;
  tr.title = title;
  tr.t_s = toVector(d.t_s);
  for (Eigen::Index k = 0; k < d.dof(); ++k) {
    tr.joints.push_back({d.joints[static_cast<std::size_t>(k)], toVector(d.q_rad.col(k)), toVector(d.tau_Nm.col(k)), {}});
  }
  const auto has = [&](const char* n) { return std::find(d.extra_names.begin(), d.extra_names.end(), n) != d.extra_names.end(); };
  if (has("base_x") && has("base_z") && has("base_pitch")) {
    tr.base_x_m = toVector(d.extraColumn("base_x"));
    tr.base_z_m = toVector(d.extraColumn("base_z"));
    tr.base_pitch_rad = toVector(d.extraColumn("base_pitch"));
  }
  return tr;
}

// The APAL leg's track: the record (--data) or a simulation's exact states; --ident's prediction
// on what a rig records (the measured angles and torques).
render::Track legTrack(const RenderArgs& a) {
  if (!a.data.empty()) {
    const ident::Dataset d = readLog(a.data, LogInput{});
    render::Track tr = trackOf(d, "recorded: " + baseName(a.data));
    if (!a.ident_json.empty()) addLegPrediction(a.ident_json, d, a.signals, tr);
    return tr;
  }
  a.sim.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const sim::SimResult r = sim::simulate(a.sim);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "simulated " << a.sim.duration_s << " s of trajectory " << a.sim.trajectory << " in " << wall << " s\n";
  render::Track tr = render::trackFromSimulation(
      r, "trajectory " + core::toText(a.sim.trajectory) + " (simulated" +
             (a.sim.variant.vibration_level > 0 ? ", vibration " + core::toText(a.sim.variant.vibration_level).substr(0, 4) : std::string()) +
             ")");
  if (!a.ident_json.empty()) addLegPrediction(a.ident_json, toDataset(r), a.signals, tr);
  return tr;
}

// Any other chain's track: its record (--data, read with the model's joints) or a simulation of
// it (exoid simulate --model's).
render::Track chainTrack(const RenderArgs& a) {
  const LoadedChain loaded = loadChain(a.sim.model_path, {}, a.selection);
  ident::Dataset d;
  std::string title;
  if (!a.data.empty()) {
    LogInput in;
    in.csv.joints = loaded.model.jointNames();
    in.angle_unit_given = true;  // exoid's own CSV convention, radians
    in.check_record = recordOfChain(loaded);
    d = readLog(a.data, in);
    title = "recorded: " + baseName(a.data);
  } else {
    sim::ChainSimConfig c = chainSimConfig(a.sim);
    c.selection = a.selection;
    d = chainDataset(sim::simulateChain(c));
    title = loaded.chain.name + " simulated (seed " + core::toText(a.sim.seed) + ")";
  }
  render::Track tr = trackOf(d, title);
  if (!a.ident_json.empty()) addPrediction(d, a.signals, loaded.robot, chainEstimateFrom(a.ident_json, loaded), "LS", tr);
  return tr;
}

void run(RenderArgs& a) {
  const bool still = a.frame_opt && a.frame_opt->count() > 0;
  if (still && !endsWithIgnoringCase(a.out, ".png")) {
    throw std::invalid_argument("--frame writes a PNG still: give --out FILE.png (got '" + a.out + "')");
  }
  if (!still && !endsWithIgnoringCase(a.out, ".mp4")) {
    throw std::invalid_argument("a video is written as H.264 MP4: give --out FILE.mp4 (got '" + a.out +
                                "'), or --frame T --out FILE.png for a still");
  }
  if (still && a.data.empty() && !(a.frame_s >= 0.0 && a.frame_s < a.sim.duration_s)) {
    throw std::invalid_argument("--frame " + core::toText(a.frame_s) + " is outside the simulated record [0, " +
                                core::toText(a.sim.duration_s) + ") s (see --duration)");
  }
  a.clip.render.multisamples = a.antialias ? 4 : 0;
  a.clip.overlay_enabled = !a.no_overlay;
  a.clip.overlay.plot = !a.no_plot;
  a.clip.validate();
  if (!a.ident_json.empty() && (a.signals.cutoff_from_data || a.signals.derivative_cutoff_from_data)) {
    throw std::invalid_argument("render's predicted torque uses the paper's signal processing: give --cutoff-hz and "
                                "--derivative-cutoff-hz as numbers, not auto");
  }
  if (!still && (a.clip.render.width % 2 != 0 || a.clip.render.height % 2 != 0)) {
    throw std::invalid_argument("an H.264 video needs an even width and height (yuv420p), got " + core::toText(a.clip.render.width) +
                                "x" + core::toText(a.clip.render.height) + ": e.g. --width " +
                                core::toText(a.clip.render.width + a.clip.render.width % 2) + " --height " +
                                core::toText(a.clip.render.height + a.clip.render.height % 2));
  }
  // Fail fast, before simulating or rendering: ffmpeg present, output folder writable.
  checkTreeSelection(a.selection, a.sim.model_path);
  a.clip.selection = a.selection;
  if (!still) render::requireFfmpeg(a.clip.ffmpeg);
  core::checkOutputWritable(a.out);
  const render::Track track = sim::isApalLegModel(a.sim.model_path) ? legTrack(a) : chainTrack(a);
  // A torque panel per joint below the text's band: 560 px (the tallest image with the small
  // font; even, as a video needs) keep three panels ~110 px each (480 px: 85); two get the APAL
  // leg's ~145.
  if (!a.no_overlay && !a.no_plot && a.height_opt->count() == 0 && track.joints.size() > 2) {
    a.clip.render.height = std::max(a.clip.render.height, 560);
  }
  if (still) {
    render::renderStill(track, a.frame_s, a.clip, a.out);
    std::cout << "wrote " << a.out << " (" << a.clip.render.width << "x" << a.clip.render.height << ", t = " << a.frame_s
              << " s)\n";
    return;
  }
  const render::ClipSummary s = render::renderVideo(track, a.clip, a.out);
  char line[256];
  std::snprintf(line, sizeof line,
                "wrote %s: %d frames, %dx%d at %g fps (%.3f s); rendering took %.2f s (%.1f ms/frame, %.2fx the clip "
                "duration)\n",
                a.out.c_str(), s.frames, a.clip.render.width, a.clip.render.height, a.clip.fps, s.clip_duration_s,
                s.wall_time_s, s.ms_per_frame, s.realtime_ratio);
  std::cout << line;
}

}  // namespace

void addRenderCommand(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  args->sim.duration_s = 5.0;
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Render the APAL leg headless (OSMesa, no display) to an H.264 MP4 (ffmpeg) or, with --frame, to one\n"
      "PNG still. Source: a simulation (default; the options of `exoid simulate`) or a recorded dataset CSV\n"
      "(--data; the recorded angles are replayed with the four-bar closure, base_x/base_z/base_pitch\n"
      "columns move the pedestal). The camera looks at the sagittal plane (x anterior to the right).\n"
      "Overlay: time, joint angles, measured torques and scrolling torque plots; with --ident, the\n"
      "identified model's predicted torques and the error (measured - predicted).\n"
      "--model leg3|FILE: any serial chain (an MJCF, or a URDF drawn as a capsule per link and a sphere at\n"
      "its COM; --base/--tip/--lock JOINT=VALUE pick it out of a tree), posed along its record or simulation,\n"
      "with the same overlay per joint (--ident: the JSON of `exoid identify --model ... --json`).\n"
      "Examples:\n"
      "  exoid render --trajectory 3 --duration 5 --out traj3.mp4\n"
      "  exoid render --data rec.csv --ident result.json --out rec.mp4\n"
      "  exoid render --trajectory 4 --frame 2.25 --out still.png\n"
      "  exoid render --model leg3 --data log.csv --ident fit.json --frame 2.5 --out leg3.png");
  cmd->add_option("--out", args->out, "Output: FILE.mp4 (video) or FILE.png (with --frame); written atomically")
      ->required()->group("Output");
  args->frame_opt = cmd->add_option("--frame", args->frame_s,
                                    "Write one PNG still of the recorded state nearest to this time (s) instead of a video")
                        ->group("Output");
  cmd->add_option("--width", args->clip.render.width, "Image width (pixels; even for video)")
      ->capture_default_str()->check(CLI::Range(16, 8192))->group("Output");
  args->height_opt = cmd->add_option("--height", args->clip.render.height,
                                     "Image height (pixels; even for video; default 480, 560 for a chain of 3+ joints with torque plots)")
      ->capture_default_str()->check(CLI::Range(16, 8192))->group("Output");
  cmd->add_option("--fps", args->clip.fps, "Video frames per second; frames sample the record at k/fps")
      ->capture_default_str()->check(CLI::Range(1e-3, 240.0))->group("Output");
  cmd->add_flag("--shadows", args->clip.render.shadows, "Shadow mapping (about 2-3x the rendering cost)")->group("Output");
  cmd->add_flag("--antialias", args->antialias, "4x multisampling (about 2x the rendering cost on llvmpipe)")
      ->group("Output");
  cmd->add_flag("--no-overlay", args->no_overlay, "No text or plots: the 3D view only")->group("Output");
  cmd->add_flag("--no-plot", args->no_plot, "Text overlay only, no torque plots")->group("Output");
  cmd->add_option("--window", args->clip.overlay.plot_window_s, "Scrolling plot window (s)")
      ->capture_default_str()->check(positiveNumber())->group("Output");
  cmd->add_option("--base-gain", args->clip.base_motion_gain,
                  "Multiply the drawn pedestal motion (1 = true size; e.g. 20 to see mm-scale vibration)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group("Output");
  cmd->add_option("--ffmpeg", args->clip.ffmpeg, "ffmpeg executable (name on PATH or a path)")
      ->capture_default_str()->group("Output");

  cmd->add_option("--data", args->data, "Replay this dataset CSV instead of simulating")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--ident", args->ident_json,
                  "Identification JSON (`exoid identify --json`): plot its predicted torque and the error")
      ->check(CLI::ExistingFile)->group("Input");

  addSimOptions(*cmd, args->sim);
  addChainSelectionOptions(*cmd, args->selection);
  cmd->add_option("--seed", args->sim.seed, "Seed of the sensor noise and floor disturbance")
      ->check(seedValidator())->capture_default_str()->group("Simulation");
  addSignalOptions(*cmd, args->signals);
  cmd->callback([args] {
    args->clip.model_path = args->sim.model_path;
    run(*args);
  });
}

}  // namespace exoid::experiments

#endif  // EXOID_WITH_RENDER
