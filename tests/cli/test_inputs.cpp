// Input expansion and the channel selection (src/workflow/inputs.hpp): a directory of text and
// HDF5 recordings, what a directory search leaves out, and --channels / --exclude-channels
// lists with '!' excludes.
#include "src/workflow/inputs.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

TEST(Inputs, ADirectoryOfTextAndHdfRecordingsIsALot) {
  const fs::path dir = test::fresh_dir("inputs_dir");
  fs::create_directories(dir / "lot" / "sub");
  for (const char* name : {"a.csv", "B.CSV.GZ", "c.tsv", "sub/d.tsv.gz", "e.h5", "f.HDF5",
                           "notes.txt", "g.dat", "lot_summary.csv", "u.allan.h5", ".hidden.csv"})
    std::ofstream(dir / "lot" / name) << "x\n";
  const workflow::InputList in = workflow::expand_inputs({(dir / "lot").string()});
  std::vector<std::string> names;
  for (const std::string& f : in.files)
    names.push_back(fs::relative(f, dir / "lot").string());
  EXPECT_EQ(names, (std::vector<std::string>{"B.CSV.GZ", "a.csv", "c.tsv", "e.h5", "f.HDF5",
                                             "sub/d.tsv.gz"}));
  EXPECT_TRUE(in.failures.empty());

  fs::create_directories(dir / "empty");
  std::ofstream(dir / "empty" / "README.txt") << "x\n";
  const workflow::InputList none = workflow::expand_inputs({(dir / "empty").string()});
  ASSERT_EQ(none.failures.size(), 1u);
  EXPECT_EQ(none.failures[0].second,
            "directory contains no recording (looked for *.h5, *.hdf5, *.csv, *.tsv, *.csv.gz, "
            "*.tsv.gz, *.bag, *.mcap, *.db3; give other files by name)");
}

TEST(Inputs, ChannelSelectionListsAndExcludes) {
  const workflow::ChannelSelection all;
  EXPECT_TRUE(all.selects_all());
  EXPECT_TRUE(all.selects("/temp"));
  EXPECT_EQ(all.text(), "");

  const workflow::ChannelSelection imu({"gyro_*, accel_*", "/mag/*"}, {});
  for (const char* p : {"/imu/gyro_x", "/gyro_y", "/accel_z", "/mag/x"})
    EXPECT_TRUE(imu.selects(p)) << p;
  for (const char* p : {"/temp", "/imu/temp", "/x/mag"})
    EXPECT_FALSE(imu.selects(p)) << p;
  EXPECT_EQ(imu.text(), "gyro_*,accel_*,/mag/*");
  EXPECT_EQ(imu.unmatched({"/gyro_x", "/gyro_y"}), (std::vector<std::string>{"accel_*", "/mag/*"}));

  const workflow::ChannelSelection bang({"!temp*"}, {});
  const workflow::ChannelSelection excl({}, {"temp*"});
  for (const workflow::ChannelSelection* s : {&bang, &excl}) {
    EXPECT_TRUE(s->selects("/gyro_x"));
    EXPECT_FALSE(s->selects("/temp"));
    EXPECT_FALSE(s->selects("/imu/temp_board"));
    EXPECT_EQ(s->text(), "!temp*");
    EXPECT_TRUE(s->unmatched({"/gyro_x"}).empty());
  }
  const workflow::ChannelSelection both({"gyro_*"}, {"*_z"});
  EXPECT_TRUE(both.selects("/gyro_x"));
  EXPECT_FALSE(both.selects("/gyro_z"));
  EXPECT_EQ(both.text(), "gyro_*,!*_z");
  // A single glob reads as given: the resume stamp of results written before lists stays.
  EXPECT_EQ(workflow::ChannelSelection({"gyro_*"}, {}).text(), "gyro_*");
  EXPECT_THROW(workflow::ChannelSelection({"gyro_*,!"}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
