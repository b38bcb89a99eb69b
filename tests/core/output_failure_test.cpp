// Output failure paths not covered by io_test.cpp (which has the missing
// folder, RLIMIT_FSIZE as a full disk, a read-only folder and a throwing
// callback): device destinations such as /dev/full and /dev/null.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <ostream>
#include <stdexcept>
#include <string>

#include "podid/core/io.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

bool IsCharacterDevice(const char* path) {
  struct stat status {};
  return ::stat(path, &status) == 0 && S_ISCHR(status.st_mode);
}

TEST(OutputFailure, DevFullIsAClearErrorAndStaysADevice) {
  // Writing through a temporary and renaming it onto /dev/full used to
  // replace the device node with a regular file (when /dev is writable, as for
  // root). A device is now written in place: /dev/full says ENOSPC.
  if (!IsCharacterDevice("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically("/dev/full",
                          [](std::ostream& os) { os << std::string(1 << 20, 'x'); }),
      std::runtime_error, "cannot write /dev/full: No space left on device");
  EXPECT_TRUE(IsCharacterDevice("/dev/full"));
}

TEST(OutputFailure, DevNullAcceptsOutputAndStaysADevice) {
  if (!IsCharacterDevice("/dev/null")) GTEST_SKIP() << "no /dev/null here";
  EXPECT_NO_THROW(WriteFileAtomically("/dev/null", [](std::ostream& os) { os << "t,w1\n"; }));
  EXPECT_TRUE(IsCharacterDevice("/dev/null"));
}

TEST(OutputFailure, CallbackErrorOnADeviceKeepsItsKind) {
  if (!IsCharacterDevice("/dev/null")) GTEST_SKIP() << "no /dev/null here";
  PODID_EXPECT_THROW_WITH(WriteFileAtomically("/dev/null",
                                              [](std::ostream&) {
                                                throw std::invalid_argument("bad series");
                                              }),
                          std::invalid_argument, "writing /dev/null: bad series");
}

}  // namespace
}  // namespace podid
