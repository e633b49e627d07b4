#pragma once
// Reads octree/scan.dat.bz2 of the shared datasets (OctoMap's test scan: "x y z"
// lines, meters) for the octree tests and benchmark.
#include <bzlib.h>

#include <charconv>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rove::octree_test {

/// The points, parsed to the nearest float as OctoMap's reader does.
inline std::vector<Eigen::Vector3f> read_scan_dat(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot open " + path);
  std::string packed((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  bz_stream z{};
  if (BZ2_bzDecompressInit(&z, 0, 0) != BZ_OK) throw std::runtime_error("bzip2: out of memory");
  std::string text;
  char buf[1 << 16];
  z.next_in = packed.data();
  z.avail_in = static_cast<unsigned int>(packed.size());
  int rc = BZ_OK;
  while (rc == BZ_OK) {
    z.next_out = buf;
    z.avail_out = sizeof buf;
    rc = BZ2_bzDecompress(&z);
    text.append(buf, sizeof buf - z.avail_out);
  }
  BZ2_bzDecompressEnd(&z);
  if (rc != BZ_STREAM_END) throw std::runtime_error("cannot decompress " + path);
  const auto is_space = [](char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; };
  std::vector<Eigen::Vector3f> pts;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end && is_space(*p)) ++p;
  while (p < end) {
    float v[3];
    for (float& x : v) {
      while (p < end && is_space(*p)) ++p;
      const auto r = std::from_chars(p, end, x);
      if (r.ec != std::errc()) throw std::runtime_error("bad number in " + path);
      p = r.ptr;
    }
    pts.emplace_back(v[0], v[1], v[2]);
    while (p < end && is_space(*p)) ++p;
  }
  return pts;
}

}  // namespace rove::octree_test
