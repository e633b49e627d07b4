#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "rove/core/error.h"
#include "rove/serialization/file_stream.h"
#include "rove/serialization/gzip_stream.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/stl.h"
#include "test_util.h"

namespace rove {
namespace {

using test::TempDir;

struct Sample {
  std::vector<double> values;
  std::map<std::string, std::int32_t> counts;
  bool operator==(const Sample&) const = default;
};

Sample make_sample() {
  Sample s;
  for (int i = 0; i < 50000; ++i) s.values.push_back(i * 0.25);
  s.counts = {{"scans", 13631}, {"odometry", 13630}};
  return s;
}

void write_sample(OutStream& out, const Sample& s) {
  OutArchive ar(out);
  ar << s.values << s.counts;
}

Sample read_sample(InStream& in) {
  InArchive ar(in);
  Sample s;
  ar >> s.values >> s.counts;
  EXPECT_TRUE(ar.at_end());
  return s;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

TEST(Streams, PlainFileRoundTrip) {
  TempDir dir;
  const Sample s = make_sample();
  {
    FileOutStream out(dir.file("plain.bin"));
    write_sample(out, s);
    EXPECT_EQ(out.offset(), 4u + 8u * 50000u + 4u + (4 + 8 + 4) + (4 + 5 + 4));
    out.close();
  }
  FileInStream in(dir.file("plain.bin"));
  EXPECT_EQ(in.remaining(), 400037u);
  EXPECT_EQ(read_sample(in), s);
}

TEST(Streams, GzipRoundTripCompressesAndCountsDecompressedOffsets) {
  TempDir dir;
  const Sample s = make_sample();
  std::uint64_t written = 0;
  {
    GzipFileOutStream out(dir.file("sample.gz"));
    write_sample(out, s);
    written = out.offset();
    out.close();
  }
  const auto raw = file_bytes(dir.file("sample.gz"));
  ASSERT_GE(raw.size(), 2u);
  EXPECT_EQ(raw[0], 0x1f);
  EXPECT_EQ(raw[1], 0x8b);
  EXPECT_LT(raw.size(), written / 2);
  GzipFileInStream in(dir.file("sample.gz"));
  EXPECT_EQ(read_sample(in), s);
  EXPECT_EQ(in.offset(), written);
}

TEST(Streams, OpenInputFileDetectsGzipAndPlain) {
  TempDir dir;
  const Sample s = make_sample();
  {
    auto plain = open_output_file(dir.file("a.bin"), FileCompression::None);
    write_sample(*plain, s);
    auto gz = open_output_file(dir.file("a.bin.gz"), FileCompression::Gzip);
    write_sample(*gz, s);
  }
  EXPECT_FALSE(is_gzip_file(dir.file("a.bin")));
  EXPECT_TRUE(is_gzip_file(dir.file("a.bin.gz")));
  auto plain_in = open_input_file(dir.file("a.bin"));
  EXPECT_NE(dynamic_cast<FileInStream*>(plain_in.get()), nullptr);
  EXPECT_EQ(read_sample(*plain_in), s);
  auto gz_in = open_input_file(dir.file("a.bin.gz"));
  EXPECT_NE(dynamic_cast<GzipFileInStream*>(gz_in.get()), nullptr);
  EXPECT_EQ(read_sample(*gz_in), s);
  EXPECT_EQ(gz_in->source_name(), dir.file("a.bin.gz"));
}

TEST(Streams, EmptyAndOneByteFilesAreNotGzip) {
  TempDir dir;
  { FileOutStream out(dir.file("empty")); }
  EXPECT_FALSE(is_gzip_file(dir.file("empty")));
  {
    FileOutStream out(dir.file("one"));
    const std::byte b{0x1f};
    out.write(std::span<const std::byte>(&b, 1));
  }
  EXPECT_FALSE(is_gzip_file(dir.file("one")));
  auto in = open_input_file(dir.file("empty"));
  InArchive ar(*in);
  EXPECT_TRUE(ar.at_end());
}

TEST(Streams, MissingFilesGiveIoErrorWithThePath) {
  TempDir dir;
  const std::string missing = dir.file("nope/missing.bin");
  for (int kind = 0; kind < 4; ++kind) {
    try {
      switch (kind) {
        case 0: (void)std::make_unique<FileInStream>(missing); break;
        case 1: (void)std::make_unique<GzipFileInStream>(missing); break;
        case 2: (void)open_input_file(missing); break;
        default: (void)std::make_unique<FileOutStream>(missing); break;
      }
      ADD_FAILURE() << "kind " << kind;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), missing);
    }
  }
  EXPECT_THROW((void)std::make_unique<GzipFileOutStream>(missing), IoError);
  EXPECT_THROW((void)std::make_unique<GzipFileOutStream>(dir.file("x.gz"), 0), InvalidArgument);
}

TEST(Streams, TruncatedGzipGivesParseErrorAtADecompressedOffset) {
  TempDir dir;
  const Sample s = make_sample();
  {
    GzipFileOutStream out(dir.file("full.gz"));
    write_sample(out, s);
  }
  const auto raw = file_bytes(dir.file("full.gz"));
  for (const std::size_t keep : {std::size_t{5}, std::size_t{30}, raw.size() / 2, raw.size() - 4}) {
    const std::string cut = dir.file("cut.gz");
    {
      std::ofstream f(cut, std::ios::binary | std::ios::trunc);
      f.write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(keep));
    }
    auto in = open_input_file(cut);
    try {
      (void)read_sample(*in);
      ADD_FAILURE() << "kept " << keep << " bytes";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, cut);
      ASSERT_TRUE(e.location().offset.has_value());
      EXPECT_LE(*e.location().offset, 400037u);
    }
  }
}

TEST(Streams, CorruptGzipGivesParseError) {
  TempDir dir;
  {
    GzipFileOutStream out(dir.file("c.gz"));
    write_sample(out, make_sample());
  }
  auto raw = file_bytes(dir.file("c.gz"));
  for (std::size_t i = 20; i < 60; ++i) raw[i] ^= 0x5a;
  {
    std::ofstream f(dir.file("c.gz"), std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
  }
  auto in = open_input_file(dir.file("c.gz"));
  EXPECT_THROW((void)read_sample(*in), ParseError);
}

TEST(Streams, MemoryStreamsOwnedAndBorrowed) {
  MemoryOutStream out("<buf>");
  OutArchive ar(out);
  ar << std::uint32_t{7};
  EXPECT_EQ(out.source_name(), "<buf>");
  MemoryInStream owned(out.take(), "<owned>");
  EXPECT_TRUE(out.data().empty());
  EXPECT_EQ(owned.remaining(), 4u);
  InArchive in(owned);
  EXPECT_EQ(in.read_scalar<std::uint32_t>(), 7u);
  EXPECT_EQ(owned.remaining(), 0u);
}

}  // namespace
}  // namespace rove
