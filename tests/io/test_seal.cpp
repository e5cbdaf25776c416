// The seal of results files (io/seal.hpp): intact as written, damaged by any change of a byte,
// a truncation or an edit through HDF5, and absent (read as before) on a file of an earlier
// version. Every reader refuses a damaged file by name before HDF5 reads it.
#include "io/error.hpp"
#include "io/fingerprint.hpp"
#include "io/results.hpp"
#include "io/seal.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

io::RecordingResult small_result() {
  io::RecordingResult r;
  r.device_id = "SN_1";
  r.source_file = "/data/SN_1.h5";
  io::ChannelResult ch;
  ch.path = "/imu/gyro_x";
  ch.units = "deg/s";
  ch.sample_rate_hz = 100;
  ch.n_samples = 1000;
  r.channels.push_back(ch);
  return r;
}

void overwrite(const fs::path& p, std::size_t offset, const std::string& bytes) {
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(offset));
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(Seal, IntactAsWrittenDamagedByAnyChange) {
  const fs::path dir = test::fresh_dir("seal");
  const fs::path path = dir / "SN_1.allan.h5";
  io::write_results(path, small_result());
  EXPECT_EQ(io::check_seal(path).state, io::SealState::Intact);
  EXPECT_TRUE(io::require_intact(path));
  const std::string good = test::file_bytes(path);
  // One byte anywhere after the seal, the seal itself, a truncation, an extension.
  for (const std::size_t at :
       {std::size_t{600}, good.size() / 2, good.size() - 1, std::size_t{3}}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << good;
    overwrite(path, at, std::string(1, static_cast<char>(good[at] ^ 0x5a)));
    EXPECT_EQ(io::check_seal(path).state, io::SealState::Damaged) << "byte " << at;
    EXPECT_THROW(io::read_results(path), io::Error) << "byte " << at;
    EXPECT_FALSE(io::read_results_stamp(path)) << "byte " << at;
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << good.substr(0, good.size() - 100);
  EXPECT_NE(io::check_seal(path).reason.find("truncated"), std::string::npos);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << good << "tail";
  EXPECT_EQ(io::check_seal(path).state, io::SealState::Damaged);
  // Edited through HDF5: a well-formed file whose bytes are no longer what allanlot wrote.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << good;
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Adelete(f, "device_id"), 0);
    H5Fclose(f);
  }
  try {
    io::read_results(path);
    ADD_FAILURE() << "an edited file was read";
  } catch (const io::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ": damaged"), std::string::npos)
        << e.what();
  }
}

TEST(Seal, AFileOfAnEarlierVersionIsUnsealedAndReadAsBefore) {
  const fs::path path = test::fresh_dir("seal_legacy") / "old.allan.h5";
  {
    test::H5Fixture f(path);
    f.attr("/", "device_id", std::string("old"));
  }
  EXPECT_EQ(io::check_seal(path).state, io::SealState::Unsealed);
  EXPECT_FALSE(io::require_intact(path));
  EXPECT_FALSE(io::read_results_stamp(path)) << "resume trusts only sealed files";
}

TEST(Seal, ResealAfterAnEditInPlace) {
  const fs::path path = test::fresh_dir("seal_reseal") / "SN_1.allan.h5";
  io::write_results(path, small_result());
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Gclose(H5Gcreate2(f, "/notes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    H5Fclose(f);
  }
  EXPECT_EQ(io::check_seal(path).state, io::SealState::Damaged);
  io::reseal_file(path);
  EXPECT_EQ(io::check_seal(path).state, io::SealState::Intact);
  EXPECT_EQ(io::read_results(path).device_id, "SN_1");
}

}  // namespace
}  // namespace allanlot
