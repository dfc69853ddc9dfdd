// A run's output folder (host/app/run_folder.h): one run at a time, another run's files refused or
// replaced exactly, frames after a checkpoint removed on resume, the journal kept inside the folder.
#include "host/app/run_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

namespace fs = std::filesystem;
using testing::read_all;

class RunFolderTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    out_ = path("out");
  }
  RunManifest manifest() const {
    RunManifest m;
    m.scene_path = "/scenes/a.toml";
    m.scene_hash = 42;
    m.scale = 0.25;
    m.overrides = {"simulation.frames=3", "materials.glass.density=2500"};
    return m;
  }
  // A run of `frames` frames writing a set-up file, two files per frame (one in a subfolder) and
  // an index rewritten every frame.
  void write_run(int frames) {
    RunFolder folder(out_, FolderUse::kNew);
    folder.start(manifest());
    write_file_atomic(out_ + "/rest.pfr", "rest");
    for (int f = 0; f < frames; ++f) {
      folder.begin_frame(f);
      write_file_atomic(out_ + "/frame_0000" + std::to_string(f) + ".pfr", "frame");
      ensure_directory(out_ + "/render");
      write_file_atomic(out_ + "/render/frame_0000" + std::to_string(f) + ".png", "png");
      write_file_atomic(out_ + "/particles.pvd", "index " + std::to_string(f));
      folder.frame_done(f);
    }
  }
  bool has(const std::string& name) const { return fs::exists(out_ + "/" + name); }
  std::string out_;
};

TEST_F(RunFolderTest, ManifestReadsBackWhatWasWritten) {
  write_run(3);
  const std::optional<RunManifest> m = read_manifest(out_);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->scene_path, "/scenes/a.toml");
  EXPECT_EQ(m->scene_hash, 42u);
  EXPECT_EQ(m->scale, 0.25);
  EXPECT_EQ(m->overrides, manifest().overrides);
  EXPECT_EQ(m->frames_written, 2);
  EXPECT_FALSE(read_manifest(path("nothing")));
}

TEST_F(RunFolderTest, BrokenManifestIsRefusedNamingTheKey) {
  ensure_directory(out_);
  std::ofstream(out_ + "/run.manifest") << "scene_path /a\nscene_hash 12x\n";
  try {
    read_manifest(out_);
    FAIL() << "a broken manifest was read";
  } catch (const RunFolderError& e) {
    EXPECT_NE(std::string(e.what()).find("'scene_hash'"), std::string::npos) << e.what();
  }
}

TEST_F(RunFolderTest, OneRunAtATime) {
  RunFolder first(out_, FolderUse::kNew);
  try {
    RunFolder second(out_, FolderUse::kOverwrite);
    FAIL() << "two runs held one folder";
  } catch (const RunFolderError& e) {
    EXPECT_NE(std::string(e.what()).find("in use by a running perifrac"), std::string::npos) << e.what();
  }
}

// --out naming a file: the user's mistake, said so (not a failure to make a folder), for every use.
TEST_F(RunFolderTest, AFileIsNoFolder) {
  const std::string file = out_ + ".toml";
  { std::ofstream(file) << "x"; }
  for (FolderUse use : {FolderUse::kNew, FolderUse::kOverwrite, FolderUse::kResume}) {
    try {
      check_run_folder(file, use);
      ADD_FAILURE() << "a file was taken for a folder";
    } catch (const RunFolderError& e) {
      EXPECT_NE(std::string(e.what()).find("is a file, not a folder"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(testing::read_all(file), "x");
}

TEST_F(RunFolderTest, AFolderHoldingARunIsRefusedWithoutOverwrite) {
  write_run(2);
  EXPECT_THROW(check_run_folder(out_, FolderUse::kNew), RunFolderError);
  EXPECT_THROW(RunFolder(out_, FolderUse::kNew), RunFolderError);
  EXPECT_TRUE(has("frame_00001.pfr"));
}

TEST_F(RunFolderTest, OverwriteRemovesExactlyThePreviousRunsFiles) {
  write_run(3);
  std::ofstream(out_ + "/notes.txt") << "mine";
  {
    RunFolder folder(out_, FolderUse::kOverwrite);
    EXPECT_FALSE(has("frame_00000.pfr"));
    EXPECT_FALSE(has("frame_00002.pfr"));
    EXPECT_FALSE(has("rest.pfr"));
    EXPECT_FALSE(has("particles.pvd"));
    EXPECT_FALSE(has("render"));  // emptied, so removed
    EXPECT_FALSE(has("run.manifest"));
    EXPECT_FALSE(has("run.files"));
    EXPECT_TRUE(has("notes.txt"));  // not the run's
  }
  // A shorter run afterwards leaves no frame of the longer one.
  fs::remove_all(out_);
  write_run(3);
  {
    RunFolder folder(out_, FolderUse::kOverwrite);
    folder.start(manifest());
    folder.begin_frame(0);
    write_file_atomic(out_ + "/frame_00000.pfr", "new");
    folder.frame_done(0);
  }
  EXPECT_EQ(read_all(out_ + "/frame_00000.pfr"), "new");
  EXPECT_FALSE(has("frame_00001.pfr"));
}

// The replaced run's files are moved aside at once and removed beside the new run; so is a folder
// of files set aside by a run that was killed before it removed them, by the next run there, a
// resumed one included.
TEST_F(RunFolderTest, OverwriteRemovesTheFilesSetAsideByTheEnd) {
  write_run(3);
  std::ofstream(out_ + "/notes.txt") << "mine";
  const std::string left = out_ + "/" + kRemovingFolderPrefix + "1";
  const auto set_aside = [&] {
    size_t folders = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(out_))
      folders += e.path().filename().string().rfind(kRemovingFolderPrefix, 0) == 0;
    return folders;
  };
  ensure_directory(left + "/sub");
  std::ofstream(left + "/sub/0") << "a killed run's";
  {
    RunFolder folder(out_, FolderUse::kOverwrite);
    EXPECT_FALSE(has("frame_00001.pfr"));
    folder.start(manifest());
  }
  EXPECT_EQ(set_aside(), 0u);
  EXPECT_TRUE(has("notes.txt"));
  ensure_directory(left + "/sub");
  std::ofstream(left + "/sub/0") << "a killed run's";
  { RunFolder resumed(out_, FolderUse::kResume); }
  EXPECT_EQ(set_aside(), 0u);
}

TEST_F(RunFolderTest, ARunThatEndedBeforeItsFirstFrameIsTakenOver) {
  {
    RunFolder folder(out_, FolderUse::kNew);
    folder.start(manifest());
    write_file_atomic(out_ + "/rest.pfr", "rest");
  }
  EXPECT_NO_THROW(check_run_folder(out_, FolderUse::kNew));
  RunFolder again(out_, FolderUse::kNew);
  EXPECT_FALSE(has("rest.pfr"));
}

TEST_F(RunFolderTest, OutputsWithoutAManifestAreRefused) {
  ensure_directory(out_);
  std::ofstream(out_ + "/frame_00000.pfr") << "old";
  EXPECT_THROW(RunFolder(out_, FolderUse::kNew), RunFolderError);
  EXPECT_THROW(RunFolder(out_, FolderUse::kOverwrite), RunFolderError);
  EXPECT_TRUE(has("frame_00000.pfr"));
  // Other files are the user's business.
  fs::remove(out_ + "/frame_00000.pfr");
  std::ofstream(out_ + "/notes.txt") << "mine";
  EXPECT_NO_THROW(RunFolder(out_, FolderUse::kNew));
}

TEST_F(RunFolderTest, ResumeNeedsAManifest) {
  ensure_directory(out_);
  EXPECT_THROW(RunFolder(out_, FolderUse::kResume), RunFolderError);
  fs::remove_all(out_);
  write_run(2);
  RunFolder folder(out_, FolderUse::kResume);
  EXPECT_EQ(folder.found().frames_written, 1);
}

TEST_F(RunFolderTest, ResumeRemovesTheFilesWrittenAfterTheCheckpoint) {
  write_run(4);
  RunFolder folder(out_, FolderUse::kResume);
  folder.start(folder.found());
  EXPECT_EQ(folder.drop_frames_after(1), 4u);  // frames 2 and 3, and their images
  EXPECT_TRUE(has("frame_00001.pfr"));
  EXPECT_TRUE(has("render/frame_00001.png"));
  EXPECT_TRUE(has("particles.pvd"));  // first written at frame 0
  EXPECT_FALSE(has("frame_00002.pfr"));
  EXPECT_FALSE(has("render/frame_00003.png"));
  EXPECT_EQ(read_manifest(out_)->frames_written, 1);
  // The journal no longer lists them, and goes on recording.
  EXPECT_EQ(read_all(out_ + "/run.files").find("frame_00002"), std::string::npos);
  folder.begin_frame(2);
  write_file_atomic(out_ + "/frame_00002.pfr", "again");
  EXPECT_NE(read_all(out_ + "/run.files").find("2 frame_00002.pfr"), std::string::npos);
}

// A journal naming files outside the folder (edited by hand, or hostile) removes nothing there.
TEST_F(RunFolderTest, JournalPathsOutsideTheFolderAreIgnored) {
  write_run(1);
  std::ofstream(path("precious.txt")) << "keep";
  std::ofstream(out_ + "/run.files", std::ios::app)
      << "0 ../precious.txt\n0 " << path("precious.txt") << "\ngarbage line\n";
  RunFolder folder(out_, FolderUse::kOverwrite);
  EXPECT_TRUE(fs::exists(path("precious.txt")));
  EXPECT_FALSE(has("frame_00000.pfr"));
}

// Files written elsewhere while a folder's journal is open are not its files.
TEST_F(RunFolderTest, OnlyTheFoldersFilesAreJournaled) {
  RunFolder folder(out_, FolderUse::kNew);
  folder.start(manifest());
  write_file_atomic(path("elsewhere.txt"), "x");
  write_file_atomic(out_ + "/mine.txt", "x");
  const std::string journal = read_all(out_ + "/run.files");
  EXPECT_EQ(journal.find("elsewhere"), std::string::npos) << journal;
  EXPECT_NE(journal.find("-1 mine.txt"), std::string::npos) << journal;
  EXPECT_EQ(journal.find("run.manifest"), std::string::npos) << journal;
}

// A file rewritten (an index every frame, an image rendered again) is journaled once, under the
// frame it was first written for, across journals of the folder.
TEST_F(RunFolderTest, ARewrittenFileIsJournaledOnce) {
  write_run(3);
  {
    OutputJournal again(out_);  // (as `perifrac render` opens it)
    again.set_frame(1);
    write_file_atomic(out_ + "/render/frame_00001.png", "png again");
  }
  const std::string journal = read_all(out_ + "/run.files");
  auto count = [&](const std::string& line) {
    size_t n = 0;
    for (size_t at = journal.find(line); at != std::string::npos; at = journal.find(line, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("particles.pvd\n"), 1u) << journal;
  EXPECT_EQ(count("0 particles.pvd\n"), 1u) << journal;
  EXPECT_EQ(count("render/frame_00001.png\n"), 1u) << journal;
  // A resume that drops a file lets it be journaled again when it is written again.
  RunFolder folder(out_, FolderUse::kResume);
  folder.start(folder.found());
  folder.drop_frames_after(0);
  folder.begin_frame(1);
  write_file_atomic(out_ + "/render/frame_00001.png", "png");
  EXPECT_NE(read_all(out_ + "/run.files").find("1 render/frame_00001.png"), std::string::npos);
}

}  // namespace
}  // namespace pd
