#include "io/error.hpp"

#include <gtest/gtest.h>

TEST(IoError, MessageNamesFileDatasetAndReason) {
  const allanlot::io::Error e("/data/run7.h5", "/sensors/gyro_x", "H5Dread failed");
  EXPECT_STREQ(e.what(), "/data/run7.h5:/sensors/gyro_x: H5Dread failed");
  EXPECT_EQ(e.dataset(), "/sensors/gyro_x");
  const allanlot::io::Error f("/data/x.h5", "", "not an HDF5 file");
  EXPECT_STREQ(f.what(), "/data/x.h5: not an HDF5 file");
}
