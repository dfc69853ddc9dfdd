// Checkpoint and resume through the binary: a run killed (SIGKILL) at random points and resumed
// until it completes gives files identical to an uninterrupted run; SIGINT stops after a
// checkpoint, or during the set-up with nothing half-written; checkpoints of another scene, or corrupted
// ones, are refused with exit code 2.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/scene_texts.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

using testing::read_all;

// Contact, plastic history and broken bonds all carry state across a checkpoint: 16 frames of
// 20 steps.
constexpr const char* kScene = testing::kPlateImpactScene;

// Starts the binary with `args` (one thread, output to `log`); returns the child's pid.
pid_t spawn(const std::vector<std::string>& args, const std::string& log, const std::string& cwd = "") {
  const pid_t pid = fork();
  if (pid == 0) {
    setenv("OMP_NUM_THREADS", "1", 1);
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(126);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(PERIFRAC_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(PERIFRAC_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

// Exit code, or 128 + signal for a killed child.
int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int run(const std::vector<std::string>& args, const std::string& log, const std::string& cwd = "") {
  return wait_for(spawn(args, log, cwd));
}

class Resume : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    scene_ = path("scene.toml");
    std::ofstream(scene_) << kScene;
    log_ = path("log.txt");
  }
  // (A run killed before its first checkpoint is started again over its folder: --overwrite.)
  std::vector<std::string> fresh(const std::string& out, const std::string& every = "1",
                                 bool overwrite = false) const {
    std::vector<std::string> args{"run",   scene_, "--backend",          "cpu",
                                  "--out", out,    "--checkpoint-every", every};
    if (overwrite) args.push_back("--overwrite");
    return args;
  }
  // The outputs that must match between an interrupted and an uninterrupted run.
  void expect_same_outputs(const std::string& a, const std::string& b) const {
    for (const char* f : {"frame_00016.pfr", "frame_00009.pfr", "energy.csv", "fragments.csv",
                          "particles.pvd", "fragments_00016.pfg", "points_00016.ply", "fragments.obj"})
      EXPECT_TRUE(read_all(a + "/" + f) == read_all(b + "/" + f)) << f << " differs";
  }
  std::string scene_, log_;
};

TEST_F(Resume, KilledRunsResumeToTheUninterruptedResult) {
  const std::string reference = path("reference"), killed = path("killed");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run(fresh(reference, "0"), log_), 0) << read_all(log_);
  const int frame_ms =
      int(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 16);

  // Each attempt is killed at a random point 1 to 3 frames past the furthest frame on disk, a
  // random fraction into the next frame (so kills land in steps, frame writes and checkpoint
  // writes alike, and every attempt makes progress whatever the build's speed); it resumes
  // from the checkpoint when there is one.
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> frames_ahead(1, 3), into_frame_ms(0, std::max(1, frame_ms));
  auto furthest_frame = [&] {
    int furthest = -1;
    if (std::filesystem::exists(killed))
      for (const auto& e : std::filesystem::directory_iterator(killed)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("frame_", 0) == 0 && name.size() == 15 && name.substr(11) == ".pfr")
          furthest = std::max(furthest, std::stoi(name.substr(6, 5)));
      }
    return furthest;
  };
  int kills = 0, resumes = 0, code = -1;
  for (int attempt = 0; attempt < 40 && code != 0; ++attempt) {
    const bool have_checkpoint = std::filesystem::exists(killed + "/checkpoint.pck");
    std::vector<std::string> args =
        have_checkpoint ? std::vector<std::string>{"run", "--resume", killed, "--checkpoint-every", "1"}
                        : fresh(killed, "1", true);
    resumes += have_checkpoint;
    const int target = furthest_frame() + frames_ahead(rng);
    const pid_t pid = spawn(args, log_);
    int status = 0;
    while (furthest_frame() < target && waitpid(pid, &status, WNOHANG) == 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::this_thread::sleep_for(std::chrono::milliseconds(into_frame_ms(rng)));
    kill(pid, SIGKILL);
    // Still running: wait; else its status (from this call, or from the loop's when it ended there).
    code = waitpid(pid, &status, WNOHANG) == 0 ? wait_for(pid)
           : WIFEXITED(status)                 ? WEXITSTATUS(status)
                                               : 128 + WTERMSIG(status);
    kills += code == 128 + SIGKILL;
    ASSERT_TRUE(code == 0 || code == 128 + SIGKILL) << "exit " << code << "\n" << read_all(log_);
  }
  if (code != 0) {
    ASSERT_EQ(run({"run", "--resume", killed}, log_), 0) << read_all(log_);
  }
  EXPECT_GE(kills, 3);
  EXPECT_GE(resumes, 2);
  for (const auto& e : std::filesystem::directory_iterator(killed))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  expect_same_outputs(reference, killed);
}

TEST_F(Resume, InterruptWritesACheckpointAndStops) {
  const std::string reference = path("reference"), out = path("out");
  ASSERT_EQ(run(fresh(reference, "0"), log_), 0) << read_all(log_);
  const pid_t pid = spawn(fresh(out, "0"), log_);
  // Wait for the first frames, then interrupt.
  for (int i = 0; i < 200 && !std::filesystem::exists(out + "/frame_00002.pfr"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  kill(pid, SIGINT);
  const int code = wait_for(pid);
  if (code == 0) GTEST_SKIP() << "the run finished before the interrupt landed";
  EXPECT_EQ(code, 130) << read_all(log_);
  EXPECT_NE(read_all(log_).find("perifrac run --resume"), std::string::npos) << read_all(log_);
  ASSERT_TRUE(std::filesystem::exists(out + "/checkpoint.pck"));
  ASSERT_EQ(run({"run", "--resume", out}, log_), 0) << read_all(log_);
  expect_same_outputs(reference, out);
}

TEST_F(Resume, CompletedRunCanBeExtended) {
  const std::string out = path("out"), reference = path("reference");
  ASSERT_EQ(run(fresh(reference, "0"), log_), 0);
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "9", "--checkpoint-every", "9"},
                log_),
            0)
      << read_all(log_);
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "16"}, log_), 0) << read_all(log_);
  EXPECT_TRUE(read_all(reference + "/frame_00016.pfr") == read_all(out + "/frame_00016.pfr"));
  EXPECT_TRUE(read_all(reference + "/energy.csv") == read_all(out + "/energy.csv"));
}

// Killed after the last frame's checkpoint but before the end-of-run outputs: resuming writes them.
TEST_F(Resume, RunKilledAfterItsLastCheckpointIsFinished) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--checkpoint-every", "16"}, log_), 0);
  const std::string meshes = read_all(out + "/fragments.obj");
  std::filesystem::remove(out + "/fragments.obj");
  ASSERT_EQ(run({"run", "--resume", out}, log_), 0) << read_all(log_);
  EXPECT_TRUE(read_all(out + "/fragments.obj") == meshes);
}

// Free colliders carry their pose, velocities and last reaction across a checkpoint: a ball
// dropped on a block resting on the ground, and a box sliding into it, resumed half way, end as
// the uninterrupted run does, their poses (colliders_NNNNN.csv, .vtu) included.
constexpr const char* kFreeColliderScene = R"([simulation]
steps_per_frame = 100
frames = 12
dt = 2e-5
[world]
gravity = [0.0, -9.81, 0.0]
[materials.stone]
model = "bond_based"
density = 2000.0
bulk_modulus = 1e8
horizon = 3.0
strain_limit = 0.01
[[bodies]]
material = "stone"
center = [0.0, 0.025, 0.0]
size = [0.1, 0.05, 0.1]
spacing = 0.01
[[colliders]]
shape = "plane"
center = [0.0, 0.0, 0.0]
friction = 0.5
damping = 0.5
[[colliders]]
shape = "sphere"
radius = 0.03
center = [0.0, 0.09, 0.0]
velocity = [0.0, -1.0, 0.0]
density = 3000.0
damping = 0.3
[[colliders]]
shape = "box"
size = [0.04, 0.04, 0.04]
center = [-0.12, 0.02, 0.0]
velocity = [1.0, 0.0, 0.0]
density = 500.0
friction = 0.4
)";

TEST_F(Resume, FreeCollidersResumeToTheUninterruptedResult) {
  const std::string scene = path("free.toml"), reference = path("reference"), out = path("out");
  std::ofstream(scene) << kFreeColliderScene;
  ASSERT_EQ(run({"run", scene, "--backend", "cpu", "--out", reference}, log_), 0) << read_all(log_);
  ASSERT_EQ(
      run({"run", scene, "--backend", "cpu", "--out", out, "--frames", "6", "--checkpoint-every", "6"}, log_),
      0)
      << read_all(log_);
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "12"}, log_), 0) << read_all(log_);
  for (const char* f : {"frame_00012.pfr", "energy.csv", "colliders_00012.csv", "colliders_00012.vtu",
                        "colliders.pvd", "colliders.obj"})
    EXPECT_TRUE(read_all(reference + "/" + f) == read_all(out + "/" + f)) << f << " differs";
  // The ball and the box moved (and the csv is not of the first frame).
  EXPECT_NE(read_all(reference + "/colliders_00012.csv"), read_all(reference + "/colliders_00000.csv"));
}

// Refusals: exit code 2 with one line saying what is wrong.
void expect_refusal(const std::vector<std::string>& args, const std::string& log_path,
                    const std::string& what) {
  const int code = run(args, log_path);
  const std::string log = read_all(log_path);
  EXPECT_EQ(code, 2) << log;
  EXPECT_NE(log.find("error: "), std::string::npos) << log;
  EXPECT_NE(log.find(what), std::string::npos) << log;
}

TEST_F(Resume, RefusesAFolderWithoutCheckpoint) {
  std::filesystem::create_directories(path("empty"));
  expect_refusal({"run", "--resume", path("empty")}, log_, "holds no checkpoint.pck");
}

// A resume keeps checkpointing as the run was told to: killed after its resume, it would lose
// nothing past the last checkpoint.
TEST_F(Resume, KeepsTheCheckpointSettings) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "4", "--checkpoint-every", "2"},
                log_),
            0)
      << read_all(log_);
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "8"}, log_), 0) << read_all(log_);
  // The checkpoint is now frame 8's: resuming to 8 finds the run complete.
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "8"}, log_), 0) << read_all(log_);
  EXPECT_NE(read_all(log_).find("the run is complete at frame 8"), std::string::npos) << read_all(log_);
}

// A run started with a scene path relative to its working directory resumes from any other.
TEST_F(Resume, ResumesFromAnotherDirectory) {
  std::filesystem::create_directories(path("sub"));
  std::ofstream(path("sub/scene.toml")) << kScene;
  const std::string out = path("out");
  ASSERT_EQ(
      run({"run", "scene.toml", "--backend", "cpu", "--out", out, "--frames", "2", "--checkpoint-every", "2"},
          log_, path("sub")),
      0)
      << read_all(log_);
  EXPECT_EQ(run({"run", "--resume", out, "--frames", "3"}, log_, "/"), 0) << read_all(log_);
  EXPECT_TRUE(std::filesystem::exists(out + "/frame_00003.pfr"));
}

// A run moved with its scene (the scene's absolute path gone) finds it relative to the run.
TEST_F(Resume, FindsItsSceneAfterBothMoved) {
  std::filesystem::create_directories(path("project/scenes"));
  std::ofstream(path("project/scenes/scene.toml")) << kScene;
  ASSERT_EQ(run({"run", path("project/scenes/scene.toml"), "--backend", "cpu", "--out", path("project/out/a"),
                 "--frames", "2", "--checkpoint-every", "2"},
                log_),
            0)
      << read_all(log_);
  std::filesystem::rename(path("project"), path("moved"));
  EXPECT_EQ(run({"run", "--resume", path("moved/out/a"), "--frames", "3"}, log_), 0) << read_all(log_);
  EXPECT_NE(read_all(log_).find("found relative to the run"), std::string::npos) << read_all(log_);
  EXPECT_TRUE(std::filesystem::exists(path("moved/out/a/frame_00003.pfr")));
  // Gone from both places: one line saying so.
  std::filesystem::remove(path("moved/scenes/scene.toml"));
  expect_refusal({"run", "--resume", path("moved/out/a"), "--frames", "4"}, log_, "is gone");
}

TEST_F(Resume, RefusesAnotherScale) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "2", "--checkpoint-every", "2"},
                log_),
            0)
      << read_all(log_);
  expect_refusal({"run", "--resume", out, "--scale", "0.5"}, log_, "--scale 0.5 differs from the 1");
}

TEST_F(Resume, RefusesAnotherScene) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "1", "--checkpoint-every", "1"},
                log_),
            0);
  std::ofstream(path("other.toml")) << kScene << "# edited\n";
  expect_refusal({"run", path("other.toml"), "--resume", out}, log_,
                 "are not the ones the checkpoint was written from");
}

// --set overrides are part of the run: a resume repeats them, and other overrides are refused.
TEST_F(Resume, KeepsTheRunsOverrides) {
  const std::string out = path("out");
  const std::string set = "materials.metal.density=1500";
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "1", "--checkpoint-every", "1",
                 "--set", set},
                log_),
            0);
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "2"}, log_), 0) << read_all(log_);
  EXPECT_NE(read_all(log_).find("set        " + set), std::string::npos) << read_all(log_);
  expect_refusal({"run", "--resume", out, "--frames", "3", "--set", "materials.metal.density=1600"}, log_,
                 "are not the ones the checkpoint was written from");
}

TEST_F(Resume, RefusesACorruptedCheckpoint) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "1", "--checkpoint-every", "1"},
                log_),
            0);
  std::string bytes = read_all(out + "/checkpoint.pck");
  bytes[bytes.size() - 100] ^= 1;
  std::ofstream(out + "/checkpoint.pck", std::ios::binary) << bytes;
  expect_refusal({"run", "--resume", out}, log_, "checksum mismatch");
}

// ---- The run's folder (host/app/run_folder.h) through the binary ----------------------------

// A second run into a used folder is refused, naming --overwrite; with it, nothing of the first
// (longer) run is left.
TEST_F(Resume, AUsedFolderIsRefusedAndOverwriteLeavesNoStaleFrame) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "4"}, log_), 0)
      << read_all(log_);
  expect_refusal({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "2"}, log_, "--overwrite");
  EXPECT_TRUE(std::filesystem::exists(out + "/frame_00004.pfr"));
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "2", "--overwrite"}, log_), 0)
      << read_all(log_);
  EXPECT_TRUE(std::filesystem::exists(out + "/frame_00002.pfr"));
  for (const char* stale : {"frame_00003.pfr", "frame_00004.pfr", "frame_00004.vtu", "fragments_00004.pfg"})
    EXPECT_FALSE(std::filesystem::exists(out + "/" + stale)) << stale;
  EXPECT_EQ(read_all(out + "/particles.pvd").find("frame_00003"), std::string::npos);
}

// While a run holds its folder, another run into it stops at once.
TEST_F(Resume, TwoRunsCannotShareAFolder) {
  const std::string out = path("out");
  const pid_t first = spawn({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "400"}, log_);
  for (int i = 0; i < 1000 && !std::filesystem::exists(out + "/frame_00001.pfr"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::string second_log = path("second.txt");
  expect_refusal({"run", scene_, "--backend", "cpu", "--out", out, "--overwrite"}, second_log,
                 "in use by a running perifrac");
  kill(first, SIGKILL);
  wait_for(first);
}

// A checkpoint copied from another run's folder is refused before anything is written.
TEST_F(Resume, ACheckpointFromAnotherRunsFolderIsRefused) {
  const std::string a = path("a"), b = path("b");
  std::ofstream(path("other.toml")) << kScene << "# another scene\n";
  ASSERT_EQ(
      run({"run", scene_, "--backend", "cpu", "--out", a, "--frames", "2", "--checkpoint-every", "2"}, log_),
      0);
  ASSERT_EQ(run({"run", path("other.toml"), "--backend", "cpu", "--out", b, "--frames", "2",
                 "--checkpoint-every", "2"},
                log_),
            0);
  const std::string rest_before = read_all(b + "/rest.pfr"), pvd_before = read_all(b + "/particles.pvd");
  std::filesystem::copy_file(a + "/checkpoint.pck", b + "/checkpoint.pck",
                             std::filesystem::copy_options::overwrite_existing);
  expect_refusal({"run", "--resume", b, "--frames", "3"}, log_, "copied from another run's folder");
  EXPECT_EQ(read_all(b + "/rest.pfr"), rest_before);
  EXPECT_EQ(read_all(b + "/particles.pvd"), pvd_before);
}

// Frames a killed run wrote after its last checkpoint are removed when it resumes.
// Frames written after the checkpoint are computed again (the same bits); a resume that would end
// before them is refused and removes nothing.
TEST_F(Resume, ResumeRewritesFramesAfterTheCheckpointAndNeverEndsBeforeThem) {
  const std::string out = path("out");
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", out, "--frames", "6", "--checkpoint-every", "3"},
                log_),
            0);
  // The checkpoint is frame 6's; put back frame 3's as if the run had gone on after it unrecorded.
  ASSERT_EQ(run({"run", scene_, "--backend", "cpu", "--out", path("at3"), "--frames", "3",
                 "--checkpoint-every", "3"},
                log_),
            0);
  std::filesystem::copy_file(path("at3") + "/checkpoint.pck", out + "/checkpoint.pck",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string frame6 = read_all(out + "/frame_00006.pfr");
  expect_refusal({"run", "--resume", out, "--frames", "4"}, log_, "frames 5 to 6 would be removed");
  EXPECT_TRUE(std::filesystem::exists(out + "/frame_00005.pfr"));
  EXPECT_TRUE(read_all(out + "/frame_00006.pfr") == frame6);
  ASSERT_EQ(run({"run", "--resume", out, "--frames", "6"}, log_), 0) << read_all(log_);
  EXPECT_NE(read_all(log_).find("written after the checkpoint"), std::string::npos) << read_all(log_);
  EXPECT_TRUE(std::filesystem::exists(out + "/frame_00005.pfr"));
  EXPECT_TRUE(read_all(out + "/frame_00006.pfr") == frame6);
}

// SIGTERM in the middle of a long frame stops the run within a second with a checkpoint inside
// the frame; the resumed run ends with the uninterrupted run's bits.
TEST_F(Resume, SigtermStopsWithinASecondInsideALongFrame) {
  const std::string reference = path("reference"), out = path("out");
  const std::vector<std::string> long_frame{"--backend", "cpu", "--frames", "1", "--steps-per-frame", "1500"};
  auto args = [&](const std::string& folder) {
    std::vector<std::string> a{"run", scene_, "--out", folder};
    a.insert(a.end(), long_frame.begin(), long_frame.end());
    return a;
  };
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run(args(reference), log_), 0) << read_all(log_);
  const double frame_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (frame_seconds < 1.5)
    GTEST_SKIP() << "the frame took " << frame_seconds << " s: too short to interrupt inside";

  const pid_t pid = spawn(args(out), log_);
  for (int i = 0; i < 1000 && !std::filesystem::exists(out + "/frame_00000.pfr"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGTERM);
  const auto t_signal = std::chrono::steady_clock::now();
  const int code = wait_for(pid);
  const double stop_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_signal).count();
  ASSERT_EQ(code, 130) << read_all(log_);
  EXPECT_LT(stop_seconds, 1.0);
  EXPECT_NE(read_all(log_).find("interrupted in frame 1 at step"), std::string::npos) << read_all(log_);
  EXPECT_FALSE(std::filesystem::exists(out + "/frame_00001.pfr"));
  ASSERT_EQ(run({"run", "--resume", out}, log_), 0) << read_all(log_);
  EXPECT_TRUE(read_all(reference + "/frame_00001.pfr") == read_all(out + "/frame_00001.pfr"));
  EXPECT_TRUE(read_all(reference + "/energy.csv") == read_all(out + "/energy.csv"));
}

// SIGINT during the set-up (here while TetGen runs: a fake one sends it, as a terminal's Ctrl-C
// reaches both) stops the run between two stages with one line and exit code 130: TetGen is
// killed, nothing is left half-written, and the next run in the folder needs no --overwrite.
TEST_F(Resume, InterruptDuringTheSetUpStopsItCleanly) {
  const std::string bin = path("bin"), out = path("out"), scene = path("tets.toml");
  std::filesystem::create_directories(bin);
  std::ofstream(bin + "/tetgen") << "#!/bin/sh\nkill -INT $PPID\nexec sleep 60\n";
  std::filesystem::permissions(bin + "/tetgen", std::filesystem::perms::owner_all);
  std::ofstream(scene)
      << "[simulation]\nframes = 1\nsteps_per_frame = 2\ndt = \"auto\"\n"
         "[materials.m]\nmodel = \"bond_based\"\ndensity = 1000.0\nbulk_modulus = 1e9\nstrain_limit = 0.01\n"
         "[[bodies]]\nmaterial = \"m\"\nparticles = \"tets\"\nsize = [0.01, 0.01, 0.01]\n"
         "spacing = 0.002\n";
  const std::string saved_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (bin + ":" + saved_path).c_str(), 1);
  setenv("PERIFRAC_TET_CACHE", path("cache").c_str(), 1);
  const auto start = std::chrono::steady_clock::now();
  const int code = run({"run", scene, "--backend", "cpu", "--out", out}, log_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  setenv("PATH", saved_path.c_str(), 1);
  unsetenv("PERIFRAC_TET_CACHE");
  EXPECT_EQ(code, 130) << read_all(log_);
  EXPECT_NE(read_all(log_).find("interrupted during TetGen (SIGINT): no frame written"), std::string::npos)
      << read_all(log_);
  EXPECT_LT(seconds, 30);  // (the fake TetGen would sleep 60 s)
  if (std::filesystem::exists(out)) {
    for (const auto& e : std::filesystem::directory_iterator(out)) {
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
    }
  }
}

}  // namespace
}  // namespace pd
