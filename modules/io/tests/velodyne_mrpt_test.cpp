// decode_velodyne_scan against MRPT 2.5.8's generatePointCloud on the
// VLP-16 scan of MRPT's test data and on synthetic VLP-16, HDL-32E and
// dual-return scans MRPT wrote (references by tools/mrpt_obs_reference,
// `velodyne-cloud`; commands in docs/mrpt-files.md): parity of
// VelodyneDecoding::Mrpt (VelodyneMrptCompat, label mrpt_compat), and the
// full decoding holding MRPT's points (VelodyneMrptData).
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/io/any_rawlog.h"
#include "rove/obs/velodyne_decode.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";

std::vector<std::shared_ptr<const VelodyneScan>> velodyne_scans(const std::string& path) {
  std::vector<std::shared_ptr<const VelodyneScan>> out;
  for (const RawlogEntry& e : load_any_rawlog(path).entries) {
    if (const auto* o = std::get_if<std::shared_ptr<const Observation>>(&e)) {
      if (auto v = std::dynamic_pointer_cast<const VelodyneScan>(*o)) out.push_back(v);
    }
  }
  return out;
}

// One scan of a reference file: its count, sums and every 16th point.
struct RefScan {
  std::size_t n = 0;
  double sum[4] = {0, 0, 0, 0};
  std::vector<std::pair<std::size_t, std::array<double, 4>>> samples;
};

std::vector<RefScan> read_reference(const std::string& name) {
  std::ifstream f(kData + name);
  EXPECT_TRUE(f.good()) << name;
  std::vector<RefScan> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    if (line.rfind("scan ", 0) == 0) {
      std::string word;
      int k = 0;
      RefScan s;
      in >> word >> k >> s.n >> s.sum[0] >> s.sum[1] >> s.sum[2] >> s.sum[3];
      out.push_back(s);
      continue;
    }
    std::size_t i = 0;
    std::array<double, 4> p{};
    in >> i >> p[0] >> p[1] >> p[2] >> p[3];
    out.back().samples.emplace_back(i, p);
  }
  return out;
}

// The decoded cloud equals MRPT's: count, sums (in double over floats, so
// equal up to the last bits when every point is) and the sampled points.
void expect_cloud_equals(const VelodynePointCloud& c, const RefScan& ref) {
  ASSERT_EQ(c.x.size(), ref.n);
  double sum[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < c.x.size(); ++i) sum[0] += c.x[i], sum[1] += c.y[i], sum[2] += c.z[i], sum[3] += c.intensity[i];
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(sum[a], ref.sum[a], 1e-9 * (1.0 + std::fabs(ref.sum[a]))) << "axis " << a;
  for (const auto& [i, p] : ref.samples) {
    ASSERT_LT(i, c.x.size());
    EXPECT_NEAR(c.x[i], p[0], 1e-6 * (1.0 + std::fabs(p[0]))) << "point " << i;
    EXPECT_NEAR(c.y[i], p[1], 1e-6 * (1.0 + std::fabs(p[1]))) << "point " << i;
    EXPECT_NEAR(c.z[i], p[2], 1e-6 * (1.0 + std::fabs(p[2]))) << "point " << i;
    EXPECT_EQ(c.intensity[i], p[3]) << "point " << i;
  }
}

TEST(VelodyneMrptCompat, Vlp16ScanDecodesAsMrpts) {
  const auto scans = velodyne_scans(test_data::bundled_file("mrpt/test_velodyne_VLP16.rawlog"));
  const auto ref = read_reference("mrpt_ref_test_velodyne_VLP16_cloud.txt");
  ASSERT_EQ(scans.size(), 1u);
  ASSERT_EQ(ref.size(), 1u);
  ASSERT_TRUE(scans[0]->point_cloud.x.empty());  // raw packets only
  const VelodyneDecodeResult m = decode_velodyne_scan(*scans[0], {.decoding = VelodyneDecoding::Mrpt});
  ASSERT_TRUE(m.ok()) << m.message;
  expect_cloud_equals(m.cloud, ref[0]);
}

TEST(VelodyneMrptCompat, SyntheticScansWithCorrectionsDecodeAsMrpts) {
  const auto scans = velodyne_scans(kData + "mrpt_synthetic_velodyne.rawlog");
  const auto ref = read_reference("mrpt_ref_synthetic_velodyne_cloud.txt");
  ASSERT_EQ(scans.size(), 3u);  // VLP-16, HDL-32E, VLP-16 dual return
  ASSERT_EQ(ref.size(), 3u);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    SCOPED_TRACE(k);
    const VelodyneDecodeResult m = decode_velodyne_scan(*scans[k], {.decoding = VelodyneDecoding::Mrpt});
    ASSERT_TRUE(m.ok()) << m.message;
    expect_cloud_equals(m.cloud, ref[k]);
  }
}

TEST(VelodyneMrptData, FullDecodingHoldsMrptsPointsAndTheSecondHalfOfEveryBlock) {
  const auto scans = velodyne_scans(test_data::bundled_file("mrpt/test_velodyne_VLP16.rawlog"));
  ASSERT_EQ(scans.size(), 1u);
  const VelodyneDecodeResult m = decode_velodyne_scan(*scans[0], {.decoding = VelodyneDecoding::Mrpt});
  ASSERT_EQ(m.cloud.x.size(), read_reference("mrpt_ref_test_velodyne_VLP16_cloud.txt").at(0).n);
  // The full decoding holds MRPT's points and the second firing sequence of
  // every block as well. MRPT's azimuths differ from the exact ones by up to
  // 0.025°: rounded to 0.01°, taken from a table whose angles drift by up to
  // 0.01° from i · 0.01°, and a slightly different median step.
  const VelodyneDecodeResult f = decode_velodyne_scan(*scans[0]);
  ASSERT_TRUE(f.ok()) << f.message;
  EXPECT_GT(f.cloud.x.size(), 2 * m.cloud.x.size() - m.cloud.x.size() / 10);
  std::size_t j = 0, matched = 0;
  for (std::size_t i = 0; i < f.cloud.x.size() && j < m.cloud.x.size(); ++i) {
    const double dx = f.cloud.x[i] - m.cloud.x[j], dy = f.cloud.y[i] - m.cloud.y[j], dz = f.cloud.z[i] - m.cloud.z[j];
    const double range = std::hypot(m.cloud.x[j], m.cloud.y[j]);
    if (f.cloud.laser_id[i] == m.cloud.laser_id[j] && std::fabs(dz) < 1e-5 &&
        std::hypot(dx, dy) <= range * 0.025 * std::numbers::pi / 180.0 + 1e-5) {
      ++j, ++matched;
    }
  }
  EXPECT_EQ(matched, m.cloud.x.size());
}

TEST(VelodyneMrptData, ScanWithoutCalibrationIsNotDecoded) {
  const auto uncalibrated = velodyne_scans(kData + "mrpt_synthetic_velodyne_uncalibrated.rawlog");
  ASSERT_EQ(uncalibrated.size(), 1u);
  const VelodyneDecodeResult r = decode_velodyne_scan(*uncalibrated[0]);
  EXPECT_EQ(r.termination, VelodyneDecodeTermination::NoCalibration);
  EXPECT_TRUE(r.cloud.x.empty());
}

}  // namespace
}  // namespace rove
