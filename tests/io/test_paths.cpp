// What a path is before allanlot reads or writes it (io/paths.hpp, docs/reliability.md
// "Inputs and outputs"): one file under two names (a hard link, a symbolic link, another
// spelling) is one file, an output never replaces an input or another output, an input that is
// not a regular file is named for what it is, and only the temporaries of dead writers are
// cleaned up.
#include "io/paths.hpp"

#include "io/atomic_file.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace allanlot::io {
namespace {

namespace fs = std::filesystem;

TEST(Paths, LinksAndOtherSpellingsAreTheSameFile) {
  const fs::path dir = test::fresh_dir("paths_same");
  std::ofstream(dir / "a.h5") << "a";
  std::ofstream(dir / "b.h5") << "b";
  fs::create_hard_link(dir / "a.h5", dir / "hard.h5");
  fs::create_symlink(dir / "a.h5", dir / "soft.h5");
  EXPECT_TRUE(same_file(dir / "a.h5", dir / "hard.h5"));
  EXPECT_TRUE(same_file(dir / "a.h5", dir / "soft.h5"));
  EXPECT_TRUE(same_file(dir / "a.h5", dir / "." / ".." / dir.filename() / "a.h5"));
  EXPECT_FALSE(same_file(dir / "a.h5", dir / "b.h5"));
  EXPECT_FALSE(same_file(dir / "a.h5", dir / "absent.h5"));  // a missing file is no file

  const std::vector<fs::path> inputs = {dir / "b.h5", dir / "a.h5"};
  EXPECT_EQ(replaced_input(dir / "soft.h5", inputs), dir / "a.h5");
  EXPECT_EQ(replaced_input(dir / "new.h5", inputs), std::nullopt);
  // An input that vanished since it was listed is still not to be replaced.
  const std::vector<fs::path> gone = {dir / "gone.h5"};
  EXPECT_EQ(replaced_input(dir / "." / "gone.h5", gone), dir / "gone.h5");
}

TEST(Paths, AnOutputNeverReplacesAnInputOrAnotherOutput) {
  const fs::path dir = test::fresh_dir("paths_conflict");
  std::ofstream(dir / "in.h5") << "in";
  fs::create_symlink(dir / "in.h5", dir / "link.h5");
  const std::vector<fs::path> inputs = {dir / "in.h5"};
  const std::vector<fs::path> fine = {dir / "report.html", fs::path(), dir / "export.csv"};
  EXPECT_EQ(outputs_conflict(fine, inputs), "");  // an empty output is no output

  const std::vector<fs::path> over_link = {dir / "link.h5"};
  EXPECT_EQ(outputs_conflict(over_link, inputs), "output " + (dir / "link.h5").string() +
                                                     " is the input " + (dir / "in.h5").string() +
                                                     " (the same file); it would be overwritten");
  const std::vector<fs::path> twice = {dir / "x.csv", dir / "x.csv"};
  EXPECT_EQ(outputs_conflict(twice, inputs), "outputs " + (dir / "x.csv").string() + " and " +
                                                 (dir / "x.csv").string() + " are the same file");
  EXPECT_EQ(replaced_input_message("in.h5", "in.h5"),
            "output in.h5 is the input in.h5; it would be overwritten");
}

TEST(Paths, AnInputThatIsNotARegularFileIsNamedForWhatItIs) {
  const fs::path dir = test::fresh_dir("paths_inputs");
  std::ofstream(dir / "ok.csv") << "t,x\n";
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_EQ(input_file_problem(dir / "ok.csv"), "");
  EXPECT_EQ(input_file_problem(dir / "absent.csv"), "no such file");
  EXPECT_EQ(input_file_problem(dir), "is a directory");
  EXPECT_EQ(input_file_problem(dir / "pipe"), "not a regular file (a FIFO)");
  EXPECT_EQ(input_file_problem("/dev/null"), "not a regular file (a device)");
}

TEST(Paths, OnlyTheTemporariesOfDeadWritersOlderThanTheRunAreRemoved) {
  const fs::path dir = test::fresh_dir("paths_stale");
  const std::string host = host_tag();
  // A pid above Linux's largest (2^22) belongs to no live process; ours is alive.
  const std::string dead = ".r.h5.tmp." + host + ".99999999.0123abcd";
  const std::string alive = ".s.h5.tmp." + host + "." + std::to_string(::getpid()) + ".ff";
  const std::string other_host = ".t.h5.tmp.elsewhere.1.ab";
  const std::string not_ours = ".u.h5.tmp.x";  // not io::AtomicFile's pattern
  for (const std::string& name : {dead, alive, other_host, not_ours, std::string("r.h5")})
    std::ofstream(dir / name) << "x";
  std::ofstream(dir / (".v.h5.tmp." + host + ".99999998.cd")) << "x";
  const auto run_start = fs::last_write_time(dir / dead) + std::chrono::seconds(1);
  fs::last_write_time(dir / (".v.h5.tmp." + host + ".99999998.cd"),
                      run_start + std::chrono::seconds(1));  // written during this run

  EXPECT_EQ(remove_stale_temporaries(dir, run_start), 2u);  // the dead writer's, elsewhere's
  EXPECT_FALSE(fs::exists(dir / dead));
  EXPECT_FALSE(fs::exists(dir / other_host));
  EXPECT_TRUE(fs::exists(dir / alive));
  EXPECT_TRUE(fs::exists(dir / not_ours));
  EXPECT_TRUE(fs::exists(dir / "r.h5"));
  EXPECT_TRUE(fs::exists(dir / (".v.h5.tmp." + host + ".99999998.cd")));
}

}  // namespace
}  // namespace allanlot::io
