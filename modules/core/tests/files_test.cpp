#include "rove/core/files.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "rove/core/error.h"

namespace fs = std::filesystem;

namespace {

class FilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rove_files_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  static void put(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
  }
  // Files in dir_ other than those named.
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }
  fs::path dir_;
};

TEST_F(FilesTest, AtomicWriteReplacesOnlyOnSuccess) {
  const fs::path out = dir_ / "result.txt";
  put(out, "old result");
  EXPECT_THROW(rove::write_file_atomically(out,
                                           [](const fs::path& tmp) {
                                             put(tmp, "partial");
                                             throw std::runtime_error("writer failed half-way");
                                           }),
               std::runtime_error);
  EXPECT_EQ(slurp(out), "old result");
  EXPECT_EQ(entries(), 1u) << "the temporary file must be removed";

  rove::write_file_atomically(out, [](const fs::path& tmp) { put(tmp, "new result"); });
  EXPECT_EQ(slurp(out), "new result");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(FilesTest, AtomicOutputFileUncommittedLeavesNothing) {
  const fs::path out = dir_ / "a.bin";
  {
    rove::AtomicOutputFile f(out);
    f.write("abc");
    EXPECT_TRUE(fs::exists(f.temporary_path()));
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(entries(), 0u);
  rove::AtomicOutputFile g(out);
  g.write("xyz");
  g.commit();
  EXPECT_EQ(slurp(out), "xyz");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(FilesTest, AtomicWriteIntoMissingFolderNamesIt) {
  try {
    rove::write_text_file_atomically(dir_ / "nope" / "x.txt", "1");
    FAIL() << "expected IoError";
  } catch (const rove::IoError& e) {
    EXPECT_NE(std::string(e.message()).find("does not exist"), std::string::npos) << e.message();
  }
}

TEST_F(FilesTest, OutputEqualToInputIsRefusedThroughLinksAndDots) {
  const fs::path in = dir_ / "log.rawlog";
  put(in, "precious");
  fs::create_hard_link(in, dir_ / "hard.rawlog");
  fs::create_symlink(in, dir_ / "soft.rawlog");
  for (const fs::path& out : {in, dir_ / "." / "log.rawlog", dir_ / "hard.rawlog",
                              dir_ / "soft.rawlog"}) {
    EXPECT_THROW(rove::check_outputs_distinct({in}, {out}), rove::IoError) << out;
  }
  EXPECT_NO_THROW(rove::check_outputs_distinct({in}, {dir_ / "other.rawlog"}));
  EXPECT_THROW(rove::check_outputs_distinct({in}, {dir_ / "o", dir_ / "./o"}), rove::IoError);
  EXPECT_THROW(rove::check_outputs_distinct({in}, {dir_}), rove::IoError);
  EXPECT_THROW(rove::check_outputs_distinct({in}, {"/dev/null"}), rove::IoError);
  EXPECT_EQ(slurp(in), "precious");
}

TEST_F(FilesTest, NonRegularInputsAreRefusedWithoutReading) {
  EXPECT_THROW(rove::check_regular_input("/dev/zero", "config file"), rove::IoError);
  EXPECT_THROW(rove::read_input_file("/dev/urandom", 1 << 20, "graph"), rove::IoError);
  EXPECT_THROW(rove::check_regular_input(dir_, "map"), rove::IoError);
  EXPECT_THROW(rove::check_regular_input(dir_ / "missing.ini"), rove::IoError);
  try {
    rove::check_regular_input("/dev/zero", "config file");
  } catch (const rove::IoError& e) {
    EXPECT_EQ(e.path(), "/dev/zero");
    EXPECT_NE(e.message().find("not a regular file"), std::string::npos) << e.message();
  }
}

TEST_F(FilesTest, ReadInputFileEnforcesItsLimit) {
  const fs::path p = dir_ / "c.ini";
  put(p, std::string(100, 'x'));
  EXPECT_EQ(rove::read_input_file(p, 100).size(), 100u);
  EXPECT_THROW(rove::read_input_file(p, 99), rove::IoError);
}

TEST(Printable, EscapesControlAndInvalidUtf8AndKeepsValidUtf8) {
  EXPECT_EQ(rove::printable("plain/path.ini"), "plain/path.ini");
  EXPECT_EQ(rove::printable("caf\xc3\xa9"), "caf\xc3\xa9");
  EXPECT_EQ(rove::printable("a\x1b[31mb"), "a\\x1b[31mb");
  EXPECT_EQ(rove::printable("bad\xff\xfe"), "bad\\xff\\xfe");
  EXPECT_EQ(rove::printable("\xe0\x80\x80"), "\\xe0\\x80\\x80");  // overlong
  EXPECT_EQ(rove::printable("trunc\xe2\x82"), "trunc\\xe2\\x82");
}

}  // namespace
