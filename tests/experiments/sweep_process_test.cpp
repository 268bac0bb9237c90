// The real `exoid` binary as a child process: SIGKILL mid-sweep and resume; and the cluster
// path, a local single-node Slurm running the sweep as a job array (skipped unless slurm-wlm is
// installed: scripts/deps.sh --with-slurm).
#include "sweep_test_support.hpp"

#include <arpa/inet.h>
#include <csignal>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace exoid::experiments {
namespace {

namespace fs = std::filesystem;
using test::expectSameSweep;
using test::freshDir;
using test::referenceSweep;
using test::slurp;
using test::tinySweepArgs;

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv;
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(EXOID_BINARY, argv.data());
    ::_exit(127);
  }
  return pid;
}

std::vector<std::string> binaryArgs(std::vector<std::string> args) {
  args.insert(args.begin(), EXOID_BINARY);
  return args;
}

int waitExit(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// Finished job files only: a run's file is written as "job-....json.tmp.PID.N" and renamed, and a
// SIGKILL between the two leaves the temporary, which is not a finished run.
long jobFiles(const std::string& dir) {
  if (!fs::exists(dir + "/runs")) return 0;
  long n = 0;
  for (const auto& e : fs::directory_iterator(dir + "/runs")) {
    const std::string name = e.path().filename().string();
    n += name.rfind("job-", 0) == 0 && e.path().extension() == ".json" ? 1 : 0;
  }
  return n;
}

TEST(SweepProcess, KilledWithSigkillAndRestartedLosesNothing) {
  const std::string d = freshDir("killed");
  std::vector<std::string> args = tinySweepArgs(d);
  args.insert(args.end(), {"--threads", "1"});
  const pid_t pid = spawn(binaryArgs(args), d + ".log1");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (jobFiles(d) == 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  EXPECT_EQ(waitExit(pid), -SIGKILL);
  const long finished = jobFiles(d);
  ASSERT_GE(finished, 1);
  ASSERT_LT(finished, 4) << "the sweep finished before it was killed: the test proves nothing";
  EXPECT_FALSE(fs::exists(d + "/summary.json"));
  // Restarted with the same command: resumes, runs only the rest, and matches an uninterrupted run.
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log2")), 0);
  EXPECT_NE(slurp(d + ".log2").find(std::to_string(finished) + " already finished, resuming"), std::string::npos)
      << slurp(d + ".log2");
  expectSameSweep(d, referenceSweep());
  // Once more: nothing to do.
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log3")), 0);
  EXPECT_NE(slurp(d + ".log3").find("nothing to do"), std::string::npos) << slurp(d + ".log3");
}

// Killed (as by a power cut) while writing the tables, then while writing the plots: the folder
// is not marked complete, and the same command again finishes every output (it used to say
// "nothing to do" with summary.md, the plots and timing.json missing).
TEST(SweepProcess, KilledWhileWritingTablesOrPlotsTheRerunFinishesThem) {
  for (const std::string point : {"sweep-tables", "sweep-plots"}) {
    const std::string d = freshDir("killed_" + point);
    std::vector<std::string> args = tinySweepArgs(d);
    if (point == "sweep-plots") args.erase(std::find(args.begin(), args.end(), "--no-plots"));
    ::setenv("EXOID_TEST_KILL_AT", point.c_str(), 1);
    const pid_t pid = spawn(binaryArgs(args), d + ".log1");
    ::unsetenv("EXOID_TEST_KILL_AT");
    ASSERT_EQ(waitExit(pid), -SIGKILL) << point << ": " << slurp(d + ".log1");
    EXPECT_TRUE(fs::exists(d + "/summary.json")) << point;
    EXPECT_FALSE(fs::exists(d + "/complete.json")) << point;
    EXPECT_FALSE(fs::exists(d + (point == "sweep-tables" ? "/summary.md" : "/timing.json"))) << point;
    ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log2")), 0) << slurp(d + ".log2");
    EXPECT_NE(slurp(d + ".log2").find("writing the missing outputs"), std::string::npos) << slurp(d + ".log2");
    for (const char* f : {"summary.md", "summary.csv", "timing.json", "complete.json"}) {
      EXPECT_TRUE(fs::exists(d + "/" + f)) << point << ": " << f;
    }
    if (point == "sweep-plots") {
      EXPECT_TRUE(fs::exists(d + "/ratio_map.png") && fs::exists(d + "/error_vs_noise.png"));
    }
    expectSameSweep(d, referenceSweep());
    ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log3")), 0);
    EXPECT_NE(slurp(d + ".log3").find("nothing to do"), std::string::npos) << slurp(d + ".log3");
  }
}

// complete.json lists every output with its size and SHA-256: a rerun never says "complete" of a
// folder whose outputs are missing or were changed, rewrites them, or refuses with --keep-edits.
TEST(OutputManifest, SweepRerunRewritesMissingAndEditedOutputsOrRefusesToKeepEdits) {
  const std::string d = freshDir("manifest");
  std::vector<std::string> args = tinySweepArgs(d);
  args.erase(std::find(args.begin(), args.end(), "--no-plots"));  // the plots are outputs too
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log1")), 0) << slurp(d + ".log1");
  const std::string summary = slurp(d + "/summary.md"), timing = slurp(d + "/timing.json");
  ASSERT_TRUE(fs::exists(d + "/ratio_map.png"));
  // The measured case: timing.json and the plots removed, the same command again.
  fs::remove(d + "/timing.json");
  for (const auto& e : fs::directory_iterator(d)) {
    if (e.path().extension() == ".png") fs::remove(e.path());
  }
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log2")), 0) << slurp(d + ".log2");
  const std::string log2 = slurp(d + ".log2");
  EXPECT_EQ(log2.find("nothing to do"), std::string::npos) << log2;
  EXPECT_NE(log2.find("timing.json missing: rewriting"), std::string::npos) << log2;
  EXPECT_NE(log2.find("ratio_map.png missing: rewriting"), std::string::npos) << log2;
  EXPECT_TRUE(fs::exists(d + "/timing.json") && fs::exists(d + "/ratio_map.png"));
  // Edited by hand: rewritten from the runs (the same bytes as before the edit) ...
  std::ofstream(d + "/summary.md", std::ios::app) << "my note\n";
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log3")), 0) << slurp(d + ".log3");
  EXPECT_NE(slurp(d + ".log3").find("summary.md changed since it was written: rewriting"), std::string::npos) << slurp(d + ".log3");
  EXPECT_EQ(slurp(d + "/summary.md"), summary);
  // ... or, with --keep-edits, refused by name and left as edited.
  std::ofstream(d + "/summary.md", std::ios::app) << "my note\n";
  std::vector<std::string> keep = args;
  keep.push_back("--keep-edits");
  EXPECT_NE(waitExit(spawn(binaryArgs(keep), d + ".log4")), 0);
  EXPECT_NE(slurp(d + ".log4").find("refusing to rewrite summary.md"), std::string::npos) << slurp(d + ".log4");
  EXPECT_EQ(slurp(d + "/summary.md"), summary + "my note\n");
  // Intact again: nothing to do.
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log5")), 0);
  ASSERT_EQ(waitExit(spawn(binaryArgs(args), d + ".log6")), 0);
  EXPECT_NE(slurp(d + ".log6").find("nothing to do"), std::string::npos) << slurp(d + ".log6");
  (void)timing;
}

TEST(OutputManifest, MergeAndReproduceSayWhatTheyRewriteAndKeepEditsOnRequest) {
  // merge: two shards into M, M's summary edited, merged again.
  const std::string a = freshDir("manifest_shard0"), b = freshDir("manifest_shard1"), m = freshDir("manifest_merged");
  for (const auto& [dir, shard] : {std::pair{a, "0/2"}, std::pair{b, "1/2"}}) {
    std::vector<std::string> args = tinySweepArgs(dir);
    args.insert(args.end(), {"--shard", shard});
    ASSERT_EQ(waitExit(spawn(binaryArgs(args), dir + ".log")), 0) << slurp(dir + ".log");
  }
  const std::vector<std::string> merge = {"merge", "--out", m, "--no-plots", a, b};
  ASSERT_EQ(waitExit(spawn(binaryArgs(merge), m + ".log1")), 0) << slurp(m + ".log1");
  std::ofstream(m + "/summary.csv", std::ios::app) << "edit\n";
  std::vector<std::string> keep = merge;
  keep.push_back("--keep-edits");
  EXPECT_NE(waitExit(spawn(binaryArgs(keep), m + ".log2")), 0);
  EXPECT_NE(slurp(m + ".log2").find("refusing to rewrite summary.csv"), std::string::npos) << slurp(m + ".log2");
  ASSERT_EQ(waitExit(spawn(binaryArgs(merge), m + ".log3")), 0) << slurp(m + ".log3");
  EXPECT_NE(slurp(m + ".log3").find("summary.csv changed since it was written: rewriting"), std::string::npos) << slurp(m + ".log3");
  // reproduce: a previous run's report edited and a table removed.
  const std::string r = freshDir("manifest_reproduce");
  const std::vector<std::string> rep = {"reproduce", "--out", r, "--methods", "ls", "--no-video", "--no-plots", "--no-optimised-arm",
                                        "--duration", "3"};
  ASSERT_EQ(waitExit(spawn(binaryArgs(rep), r + ".log1")), 0) << slurp(r + ".log1");
  ASSERT_NE(slurp(r + "/complete.json").find("\"sha256\""), std::string::npos);
  const std::string report = slurp(r + "/report.md");
  std::ofstream(r + "/report.md", std::ios::app) << "edit\n";
  fs::remove(r + "/validation.csv");
  std::vector<std::string> rep_keep = rep;
  rep_keep.push_back("--keep-edits");
  EXPECT_NE(waitExit(spawn(binaryArgs(rep_keep), r + ".log2")), 0);
  EXPECT_NE(slurp(r + ".log2").find("refusing to rewrite report.md"), std::string::npos) << slurp(r + ".log2");
  EXPECT_EQ(slurp(r + "/report.md"), report + "edit\n");
  ASSERT_EQ(waitExit(spawn(binaryArgs(rep), r + ".log3")), 0) << slurp(r + ".log3");
  EXPECT_NE(slurp(r + ".log3").find("report.md changed since it was written: rewriting"), std::string::npos) << slurp(r + ".log3");
  EXPECT_NE(slurp(r + ".log3").find("validation.csv missing: rewriting"), std::string::npos) << slurp(r + ".log3");
  EXPECT_TRUE(fs::exists(r + "/validation.csv"));
}

// ---- local single-node Slurm: the daemons started by hand on a scratch slurm.conf ----

std::string findDaemon(const std::string& name) {
  for (const char* dir : {"/usr/sbin/", "/usr/bin/", "/usr/local/sbin/"}) {
    if (::access((dir + name).c_str(), X_OK) == 0) return dir + name;
  }
  return {};
}

int freePort() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(s);
  return ntohs(a.sin_port);
}

std::string capture(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  ::pclose(p);
  return out;
}

bool processGone(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  if (!stat) return true;
  std::string line;
  std::getline(stat, line);
  const auto close_paren = line.rfind(')');
  return close_paren == std::string::npos || line.substr(close_paren + 2, 1) == "Z";  // zombie: dead, awaiting reaping
}

// Starts slurmctld + slurmd on a scratch slurm.conf; stops them (SIGTERM, then SIGKILL) when destroyed.
class LocalSlurm {
 public:
  explicit LocalSlurm(const std::string& scratch) : dir_(scratch) {
    fs::create_directories(dir_ + "/state");
    fs::create_directories(dir_ + "/spool");
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    const std::string cpus = capture("nproc");
    const std::string mem = capture("free -m | awk '/Mem:/ {print $2}'");
    conf_ = dir_ + "/slurm.conf";
    std::ofstream c(conf_);
    c << "ClusterName=local\nSlurmctldHost=" << host << "(127.0.0.1)\nSlurmUser=root\nSlurmdUser=root\n"
      << "SlurmctldPort=" << freePort() << "\nSlurmdPort=" << freePort() << "\n"
      << "AuthType=auth/none\nCredType=cred/none\nStateSaveLocation=" << dir_ << "/state\nSlurmdSpoolDir=" << dir_ << "/spool\n"
      << "SlurmctldPidFile=" << dir_ << "/slurmctld.pid\nSlurmdPidFile=" << dir_ << "/slurmd.pid\n"
      << "SlurmctldLogFile=" << dir_ << "/slurmctld.log\nSlurmdLogFile=" << dir_ << "/slurmd.log\n"
      << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSelectType=select/cons_tres\nSelectTypeParameters=CR_Core\n"
      << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\nMpiDefault=none\n"
      << "ReturnToService=2\nMailProg=/bin/true\nMinJobAge=4\nSchedulerParameters=batch_sched_delay=0\n"
      << "NodeName=" << host << " NodeAddr=127.0.0.1 CPUs=" << std::stoi(cpus) << " RealMemory=" << std::stoi(mem) << " State=UNKNOWN\n"
      << "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n";
    c.close();
    ::setenv("SLURM_CONF", conf_.c_str(), 1);
    started_ = std::system((findDaemon("slurmctld") + " -f " + conf_).c_str()) == 0 &&
               std::system((findDaemon("slurmd") + " -f " + conf_).c_str()) == 0;
  }
  ~LocalSlurm() {
    for (const char* pidfile : {"/slurmd.pid", "/slurmctld.pid"}) {
      std::ifstream in(dir_ + pidfile);
      pid_t pid = 0;
      if (!(in >> pid) || pid <= 0) continue;
      ::kill(pid, SIGTERM);
      for (int i = 0; i < 100 && !processGone(pid); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (!processGone(pid)) ::kill(pid, SIGKILL);
    }
    ::unsetenv("SLURM_CONF");
  }
  bool started() const { return started_; }
  bool waitIdle() const {
    for (int i = 0; i < 300; ++i) {
      if (capture("sinfo -h -o %T 2>/dev/null").find("idle") != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }
  std::string logs() const { return slurp(dir_ + "/slurmctld.log") + slurp(dir_ + "/slurmd.log"); }

 private:
  std::string dir_, conf_;
  bool started_ = false;
};

TEST(SweepProcess, SlurmJobArrayShardsMergeToTheSingleProcessResult) {
  if (findDaemon("slurmctld").empty() || findDaemon("slurmd").empty()) {
    // The cluster path is opt-in (its packages enable system services); CI opts in and sets
    // EXOID_REQUIRE_SLURM so that a missing Slurm fails there instead of skipping.
    const char* required = std::getenv("EXOID_REQUIRE_SLURM");
    if (required != nullptr && std::string(required) == "1") {
      FAIL() << "slurmctld/slurmd not installed and EXOID_REQUIRE_SLURM=1: run scripts/deps.sh --with-slurm";
    }
    GTEST_SKIP() << "slurmctld/slurmd not installed (the cluster path is opt-in: scripts/deps.sh --with-slurm)";
  }
  const std::string scratch = freshDir("slurm");
  const LocalSlurm slurm(scratch);
  ASSERT_TRUE(slurm.started()) << slurm.logs();
  ASSERT_TRUE(slurm.waitIdle()) << "the node never became idle:\n" << slurm.logs();
  std::string cmd = std::string("exec ") + EXOID_BINARY;
  for (const std::string& a : tinySweepArgs(scratch + "/shard-$SLURM_ARRAY_TASK_ID")) cmd += " " + a;
  {
    std::ofstream job(scratch + "/job.sh");
    job << "#!/bin/sh\n" << cmd << " --threads 1\n";
  }
  const std::string sbatch = "sbatch --array=0-1 --wait --output=" + scratch + "/task-%a.out " + scratch + "/job.sh 2>&1";
  const std::string out = capture(sbatch + "; echo rc=$?");
  ASSERT_NE(out.find("rc=0"), std::string::npos) << out << slurp(scratch + "/task-0.out") << slurp(scratch + "/task-1.out");
  // Each task found its shard in the Slurm environment.
  EXPECT_NE(slurp(scratch + "/task-1.out").find("shard 1/2"), std::string::npos) << slurp(scratch + "/task-1.out");
  const std::string merged = scratch + "/merged";
  ASSERT_EQ(test::runExoid({"merge", "--no-plots", "--out", merged, scratch + "/shard-0", scratch + "/shard-1"}), 0);
  expectSameSweep(merged, referenceSweep());
}

}  // namespace
}  // namespace exoid::experiments
