// rove's MRPT readers against libmrpt 2.5.8 on every MRPT dataset: each test
// reads a file with rove, prints the same values in the same line format as
// tools/mrpt_obs_reference (which read the file with libmrpt), and compares
// the two dumps token by token: integers, labels and checksums exactly,
// floating-point values to 1e-9 (relative, or absolute below 1).

#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rove/io/mrpt_simplemap.h"
#include "rove/io/rawlog_reader.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/comment_observation.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/robot_movement_3d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/obs/velodyne_scan.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kSystem = "/usr/share/mrpt/datasets/";
const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";
constexpr int kFull = 3;

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = 1469598103934665603ULL) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ULL;
  }
  return h;
}

// Mirrors the generator's output (see tools/mrpt_obs_reference).
class Dumper {
 public:
  void f(const char* fmt, ...) __attribute__((format(printf, 2, 3))) {
    char buf[4096];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    out_ += buf;
  }
  void pose(const Pose3& p) {
    f(" %.17g %.17g %.17g %.17g %.17g %.17g", p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll());
  }
  void camera(const PinholeCamera& c) {
    f(" cam %u %u %.17g %.17g %.17g %.17g", c.width, c.height, c.fx, c.fy, c.cx, c.cy);
    for (double d : c.distortion) f(" %.17g", d);
  }
  // The generator prints MRPT's channel order (B, G, R for color).
  void image(const char* tag, const Image& im) {
    const std::size_t bpp = bytes_per_sample(im.pixel_type);
    std::uint64_t sum = 0;
    for (std::uint8_t b : im.data) sum += b;
    f(" %s %u %u %u %zu %" PRIu64, tag, im.width, im.height, im.channels, bpp, sum);
    if (im.empty()) return;
    const std::uint32_t us[3] = {0, im.width / 2, im.width - 1};
    const std::uint32_t vs[3] = {0, im.height / 2, im.height - 1};
    const std::size_t px_bytes = im.channels * bpp;
    for (int s = 0; s < 3; ++s) {
      const std::size_t at = (std::size_t{vs[s]} * im.width + us[s]) * px_bytes;
      for (std::size_t c = 0; c < px_bytes; ++c) {
        const std::size_t k = im.channels == 3 && bpp == 1 ? at + (2 - c) : at + c;
        f(" %u", im.data[k]);
      }
    }
  }

  void observation(int k, const Observation& o, bool full);
  void action(int k, const Action& a, bool full);
  void keyframe_pose(int k, const KeyframePosePdf& p);
  std::string finish() {
    for (const auto& [cls, s] : summary_) {
      f("SUM %s %zu %.17g %" PRIu64 "\n", cls.c_str(), s.count, s.sum, s.hash);
    }
    return out_;
  }

 private:
  struct Summary {
    std::size_t count = 0;
    double sum = 0.0;
    std::uint64_t hash = 1469598103934665603ULL;
  };
  std::map<std::string, Summary> summary_;
  std::string out_;
};

void Dumper::observation(int k, const Observation& o, bool full) {
  const auto head = [&](const char* cls) {
    Summary& s = summary_[cls];
    ++s.count;
    if (full) {
      f("O %d %s L=%s t=%" PRIu64, k, cls, o.sensor_label.c_str(), o.timestamp.to_mrpt());
    }
    return &s;
  };
  if (const auto* s = dynamic_cast<const RangeScan2D*>(&o)) {
    Summary* S = head("mrpt::obs::CObservation2DRangeScan");
    double sum = 0;
    for (float r : s->ranges) sum += r;
    S->sum += sum;
    if (full) {
      pose(o.T_robot_sensor);
      f(" n=%zu %.9g %.9g %.17g", s->ranges.size(), s->aperture, s->max_range, sum);
      for (std::size_t i = 0; i < std::min<std::size_t>(3, s->ranges.size()); ++i) {
        f(" %.9g %d", s->ranges[i], int(s->valid[i]));
      }
    }
  } else if (const auto* b = dynamic_cast<const BearingRange*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationBearingRange");
    double sum = 0;
    for (const auto& m : b->measurements) sum += m.range + m.yaw + m.pitch + m.landmark_id;
    S->sum += sum;
    if (full) {
      pose(o.T_robot_sensor);
      f(" n=%zu %.9g %.9g %.9g %.9g %.17g", b->measurements.size(), b->min_sensor_distance,
        b->max_sensor_distance, b->field_of_view_yaw, b->field_of_view_pitch, sum);
      for (std::size_t i = 0; i < std::min<std::size_t>(2, b->measurements.size()); ++i) {
        const auto& m = b->measurements[i];
        f(" %d %.9g %.9g %.9g", m.landmark_id, m.range, m.yaw, m.pitch);
      }
    }
  } else if (const auto* r = dynamic_cast<const BeaconRanges*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationBeaconRanges");
    double sum = 0;
    for (const auto& m : r->readings) sum += m.range + static_cast<float>(m.beacon_id);
    S->sum += sum;
    if (full) {
      f(" n=%zu %.9g %.9g %.9g %.17g", r->readings.size(), r->min_sensor_distance,
        r->max_sensor_distance, r->std_error, sum);
      if (r->aux_estimate) {
        f(" aux %.17g %.17g %.17g", r->aux_estimate->x_m, r->aux_estimate->y_m,
          r->aux_estimate->heading_rad.value_or(-INFINITY));
      } else {
        f(" aux none");
      }
    }
  } else if (const auto* c = dynamic_cast<const CommentObservation*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationComment");
    const std::uint64_t h = fnv1a(c->text.data(), c->text.size());
    S->hash = fnv1a(&h, sizeof h, S->hash);
    if (full) f(" len=%zu hash=%" PRIu64, c->text.size(), h);
  } else if (const auto* g = dynamic_cast<const GpsObservation*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationGPS");
    if (full) pose(o.T_robot_sensor);
    if (g->utc_time) {
      S->sum += g->latitude_deg + g->longitude_deg + g->altitude_m;
      if (full) {
        f(" GGA %u %u %.17g %.17g %.17g %u %.17g %u %.9g %.17g", g->utc_time->hour,
          g->utc_time->minute, g->utc_time->second, g->latitude_deg, g->longitude_deg,
          unsigned(g->fix_quality), g->altitude_m, g->satellites, g->hdop, g->geoid_separation_m);
      }
    }
    if (g->rmc) {
      const GpsRmc& m = *g->rmc;
      S->sum += m.latitude_deg + m.speed_knots;
      if (full) {
        f(" RMC %u %u %.17g %d %.17g %.17g %.17g %.17g", m.utc_time.hour, m.utc_time.minute,
          m.utc_time.second, int(m.status), m.latitude_deg, m.longitude_deg, m.speed_knots,
          m.course_deg);
      }
    }
  } else if (const auto* v = dynamic_cast<const VelodyneScan*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationVelodyneScan");
    std::uint64_t h = 1469598103934665603ULL;
    for (const auto& p : v->packets) h = fnv1a(p.data(), p.size(), h);
    S->hash = fnv1a(&h, sizeof h, S->hash);
    if (full) {
      pose(o.T_robot_sensor);
      f(" %.17g %.17g packets=%zu hash=%" PRIu64 " calib=%zu", v->min_range_m, v->max_range_m,
        v->packets.size(), h, v->calibration.size());
      if (!v->packets.empty()) {
        const auto& p0 = v->packets.front();
        const auto& pl = v->packets.back();
        f(" p0 %u %u %u %u %u %u %u", velodyne_block_header(p0, 0), velodyne_block_azimuth(p0, 0),
          velodyne_return_distance(p0, 0, 0), velodyne_return_intensity(p0, 0, 0),
          velodyne_gps_timestamp(p0), p0[1204], p0[1205]);
        f(" pl %u %u %u", velodyne_block_azimuth(pl, 11), velodyne_return_distance(pl, 11, 31),
          velodyne_gps_timestamp(pl));
      }
      if (!v->calibration.empty()) {
        f(" %.17g %.17g", v->calibration[0].vertical_correction,
          v->calibration[0].sin_vert_correction);
      }
      const auto& pc = v->point_cloud;
      double sum = 0;
      for (std::size_t i = 0; i < pc.x.size(); ++i) {
        sum += double(pc.x[i]) + pc.y[i] + pc.z[i] + pc.intensity[i];
      }
      f(" pc %zu %.17g %zu %zu %zu %zu %d", pc.x.size(), sum, pc.timestamp.size(),
        pc.azimuth.size(), pc.laser_id.size(), pc.points_for_laser_id.size(),
        int(v->has_satellite_timestamp));
      if (!pc.timestamp.empty()) f(" %" PRIu64, pc.timestamp.back().to_mrpt());
      if (!pc.azimuth.empty()) f(" %.9g %d", pc.azimuth.back(), pc.laser_id.back());
      for (const auto& ids : pc.points_for_laser_id) {
        f(" [%zu", ids.size());
        for (auto i : ids) f(" %" PRIu64, i);
        f("]");
      }
    }
  } else if (const auto* q = dynamic_cast<const RotatingScan*>(&o)) {
    Summary* S = head("mrpt::obs::CObservationRotatingScan");
    double sum = 0;
    for (std::uint16_t x : q->range) sum += x;
    S->sum += sum;
    if (full) {
      pose(o.T_robot_sensor);
      f(" %u %u %.17g %.17g %.17g %.17g %s %.17g %.17g %" PRIu64 " %d sum=%.17g", q->rows,
        q->columns, q->range_resolution_m, q->start_azimuth_rad, q->azimuth_span_rad,
        q->sweep_duration_s, q->lidar_model.c_str(), q->min_range_m, q->max_range_m,
        q->original_received_timestamp.to_mrpt(), int(q->has_satellite_timestamp), sum);
      double isum = 0;
      for (std::uint8_t x : q->intensity) isum += x;
      f(" int %d %.17g layers %zu", int(q->intensity.size()), isum, q->other_range_layers.size());
      for (const auto& [name, m] : q->other_range_layers) {
        double ls = 0;
        for (std::uint16_t x : m) ls += x;
        f(" %s %.17g", name.c_str(), ls);
      }
      if (!q->range.empty()) {
        const int rr = q->rows - 1, cc = q->columns / 2;
        f(" sample %d %d %u %u", rr, cc, q->range[0], q->range[std::size_t(rr) * q->columns + cc]);
      }
    }
  } else if (const auto* d = dynamic_cast<const RangeImage3D*>(&o)) {
    Summary* S = head("mrpt::obs::CObservation3DRangeScan");
    double psum = 0;
    const std::vector<Eigen::Vector3f> none;
    const auto& pts = d->points ? d->points->p_sensor : none;
    for (const auto& p : pts) psum += double(p.x()) + p.y() + p.z();
    S->sum += psum;
    if (full) {
      pose(o.T_robot_sensor);
      f(" %.9g %.9g %.9g %d %d", d->max_range, d->std_error_m, 1.0 / d->depth.scale,
        int(d->range_is_depth), int(d->intensity_channel));
      f(" pts %zu %.17g", pts.size(), psum);
      if (!pts.empty()) {
        const std::size_t m = pts.size() / 2;
        f(" %.9g %.9g %.9g", pts[m].x(), pts[m].y(), pts[m].z());
        std::uint64_t iu = 0, iv = 0;
        for (auto u : d->points->pixel_u) iu += u;
        for (auto v2 : d->points->pixel_v) iv += v2;
        f(" %zu %" PRIu64 " %" PRIu64, d->points->pixel_u.size(), iu, iv);
      }
      if (d->depth.pixel_count() != 0) {
        const auto& vals = std::get<std::vector<std::uint16_t>>(d->depth.values);
        std::uint64_t rs = 0;
        for (auto x : vals) rs += x;
        const std::uint32_t rr = d->depth.height / 2, cc = d->depth.width / 3;
        f(" range %u %u %" PRIu64 " %u %u %u", d->depth.height, d->depth.width, rs, rr, cc,
          vals[std::size_t(rr) * d->depth.width + cc]);
      }
      if (d->intensity) image("int", *d->intensity);
      if (d->confidence) image("conf", *d->confidence);
      camera(d->depth_camera);
      camera(d->intensity_camera);
      f(" rel");
      pose(d->T_sensor_intensity);
      f(" layers %zu", d->other_depth_layers.size());
      for (const auto& [name, m] : d->other_depth_layers) {
        std::uint64_t ls = 0;
        for (auto x : std::get<std::vector<std::uint16_t>>(m.values)) ls += x;
        f(" %s %u %u %" PRIu64, name.c_str(), m.height, m.width, ls);
      }
    }
  } else {
    ADD_FAILURE() << "unexpected observation type " << o.class_name();
  }
  if (full) f("\n");
}

void Dumper::action(int k, const Action& a, bool full) {
  if (const auto* m = dynamic_cast<const RobotMovement3D*>(&a)) {
    Summary& S = summary_["mrpt::obs::CActionRobotMovement3D"];
    ++S.count;
    const Pose3& p = m->pose_change.mean();
    S.sum += p.x() + p.y() + p.z() + m->pose_change.covariance().sum();
    if (!full) return;
    f("A %d mrpt::obs::CActionRobotMovement3D t=%" PRIu64 " %d", k, a.timestamp.to_mrpt(),
      int(m->source));
    double v[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
    if (m->velocity) {
      const Twist3& t = *m->velocity;
      const double w[6] = {t.vx, t.vy, t.vz, t.wx, t.wy, t.wz};
      std::copy(w, w + 6, v);
    }
    for (double x : v) f(" %d", int(!std::isnan(x)));
    pose(p);
    const auto& C = m->pose_change.covariance();
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) f(" %.17g", C(i, j));
    }
    for (double x : v) {
      if (std::isnan(x)) {
        f(" -");
      } else {
        f(" %.9g", x);
      }
    }
    f("\n");
  } else if (const auto* m2 = dynamic_cast<const RobotMovement2D*>(&a)) {
    Summary& S = summary_["mrpt::obs::CActionRobotMovement2D"];
    ++S.count;
    const Pose2& o = m2->odometry_increment;
    S.sum += o.x() + o.y() + o.phi();
    if (!full) return;
    f("A %d mrpt::obs::CActionRobotMovement2D t=%" PRIu64 " %.17g %.17g %.17g\n", k,
      a.timestamp.to_mrpt(), o.x(), o.y(), o.phi());
  } else {
    ADD_FAILURE() << "unexpected action type " << a.class_name();
  }
}

void Dumper::keyframe_pose(int k, const KeyframePosePdf& p) {
  const char* cls = std::visit(
      [](const auto& x) -> const char* {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Pose3Particles>) return "mrpt::poses::CPose3DPDFParticles";
        if constexpr (std::is_same_v<T, Pose3SOG>) return "mrpt::poses::CPose3DPDFSOG";
        return "mrpt::poses::CPose3DPDFGaussian";
      },
      p.pdf);
  ++summary_[cls].count;
  f("P %d %s", k, cls);
  pose(p.mean());
  if (const auto* parts = std::get_if<Pose3Particles>(&p.pdf)) {
    f(" n=%zu", parts->size());
    for (const auto& q : parts->particles()) {
      f(" %.17g", q.log_weight);
      pose(q.pose);
    }
  } else if (const auto* sog = std::get_if<Pose3SOG>(&p.pdf)) {
    f(" n=%zu", sog->size());
    for (const auto& m : sog->modes()) {
      f(" %.17g", m.log_weight);
      pose(m.gaussian.mean());
      for (int i = 0; i < 6; ++i) f(" %.17g", m.gaussian.covariance()(i, i));
      f(" %.17g", m.gaussian.covariance()(0, 5));
    }
  } else {
    const auto& g = std::get<Pose3Gaussian>(p.pdf);
    for (int i = 0; i < 6; ++i) f(" %.17g", g.covariance()(i, i));
    f(" %.17g", g.covariance()(0, 5));
  }
  f("\n");
}

std::string require_file(const std::string& path) {
  if (!std::filesystem::exists(path)) {
    ADD_FAILURE() << "dataset missing: " << path
                  << " (MRPT datasets: Debian package mrpt-common, see scripts/install-deps)";
  }
  return path;
}

std::string dump_rawlog(const std::string& path) {
  const Rawlog log = load_rawlog(path);
  Dumper d;
  const int n = static_cast<int>(log.entries.size());
  for (int k = 0; k < n; ++k) {
    const bool full = k < kFull || k >= n - kFull;
    const RawlogEntry& e = log.entries[k];
    if (const auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&e)) {
      for (const auto& a : (*ac)->actions) d.action(k, *a, full);
    } else if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&e)) {
      for (const auto& o : (*sf)->observations) d.observation(k, *o, full);
    } else {
      d.observation(k, *std::get<std::shared_ptr<const Observation>>(e), full);
    }
  }
  return d.finish();
}

std::string dump_simplemap(const std::string& path) {
  const SimpleMap map = load_mrpt_simplemap(path);
  Dumper d;
  const int n = static_cast<int>(map.keyframes.size());
  for (int k = 0; k < n; ++k) {
    const bool full = k < kFull || k >= n - kFull;
    if (full) d.keyframe_pose(k, map.keyframes[k].pose);
    for (const auto& o : map.keyframes[k].frame->observations) d.observation(k, *o, full);
  }
  return d.finish();
}

std::vector<std::string> lines_of(const std::string& text, bool skip_comments) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || (skip_comments && line[0] == '#')) continue;
    out.push_back(line);
  }
  return out;
}

// Token-by-token comparison: numbers to 1e-9, everything else exactly.
void expect_same_dump(const std::string& reference_file, const std::string& rove_dump) {
  std::ifstream in(kData + reference_file);
  ASSERT_TRUE(in.good()) << "missing reference " << reference_file;
  std::stringstream ss;
  ss << in.rdbuf();
  const auto ref = lines_of(ss.str(), true);
  const auto got = lines_of(rove_dump, false);
  ASSERT_EQ(ref.size(), got.size()) << "rove dump:\n" << rove_dump;
  for (std::size_t l = 0; l < ref.size(); ++l) {
    std::istringstream a(ref[l]), b(got[l]);
    std::vector<std::string> ta, tb;
    for (std::string t; a >> t;) ta.push_back(t);
    for (std::string t; b >> t;) tb.push_back(t);
    ASSERT_EQ(ta.size(), tb.size()) << "line " << l << "\nmrpt: " << ref[l] << "\nrove: " << got[l];
    for (std::size_t i = 0; i < ta.size(); ++i) {
      if (ta[i] == tb[i]) continue;
      char* end_a = nullptr;
      char* end_b = nullptr;
      const double x = std::strtod(ta[i].c_str(), &end_a);
      const double y = std::strtod(tb[i].c_str(), &end_b);
      const bool numbers = *end_a == '\0' && *end_b == '\0' && end_a != ta[i].c_str();
      const bool integer = ta[i].find_first_of(".eE") == std::string::npos &&
                           ta[i].find("inf") == std::string::npos;
      if (numbers && !integer && std::abs(x - y) <= 1e-9 * std::max(1.0, std::abs(x))) continue;
      ADD_FAILURE() << reference_file << " line " << l << " token " << i << ": mrpt '" << ta[i]
                    << "' rove '" << tb[i] << "'\nmrpt: " << ref[l] << "\nrove: " << got[l];
      return;
    }
  }
}

TEST(MrptPackageFiles, KfSlam6D) {
  expect_same_dump("mrpt_ref_kf_slam_6D_demo.txt",
                   dump_rawlog(require_file(kSystem + "kf-slam_6D_demo.rawlog")));
  expect_same_dump("mrpt_ref_kf_slam_6D_demo_DA.txt",
                   dump_rawlog(require_file(kSystem + "kf-slam_6D_demo_DA.rawlog")));
  expect_same_dump("mrpt_ref_kf_slam_6D_demo_noncentered.txt",
                   dump_rawlog(require_file(kSystem + "kf-slam_6D_demo_noncentered.rawlog")));
}

TEST(MrptPackageFiles, RotatingScans) {
  expect_same_dump("mrpt_ref_rot_scan_2d.txt",
                   dump_rawlog(require_file(kSystem + "rot_scan_2d.rawlog")));
  expect_same_dump("mrpt_ref_rot_scan_velodyne.txt",
                   dump_rawlog(require_file(kSystem + "rot_scan_velodyne.rawlog")));
}

TEST(MrptPackageFiles, RtkPathCommentAndGps) {
  expect_same_dump("mrpt_ref_test_rtk_path.txt",
                   dump_rawlog(require_file(kSystem + "test_rtk_path.rawlog")));
}

TEST(MrptPackageFiles, VelodyneVlp16) {
  expect_same_dump("mrpt_ref_test_velodyne_VLP16.txt",
                   dump_rawlog(require_file(test_data::bundled_file("mrpt/test_velodyne_VLP16.rawlog"))));
}

TEST(MrptPackageFiles, RgbdFrame) {
  expect_same_dump("mrpt_ref_tests_rgbd.txt", dump_rawlog(require_file(kSystem + "tests_rgbd.rawlog")));
}

TEST(MrptPackageFiles, UwbBeaconsWithUnsetHeading) {
  expect_same_dump("mrpt_ref_uwb_ro_localization_demo.txt",
                   dump_rawlog(require_file(kSystem + "uwb_ro-localization_demo.rawlog")));
  // MRPT marks the beacon system's heading as not estimated with -inf.
  const Rawlog log = load_rawlog(kSystem + "uwb_ro-localization_demo.rawlog");
  const auto& sf = std::get<std::shared_ptr<const SensoryFrame>>(log.entries[0]);
  const auto beacons = sf->find<BeaconRanges>();
  ASSERT_NE(beacons, nullptr);
  ASSERT_TRUE(beacons->aux_estimate.has_value());
  EXPECT_FALSE(beacons->aux_estimate->heading_rad.has_value());
}

TEST(MrptPackageFiles, GraphSlamEngineDemos) {
  const std::string dir = kSystem + "graphslam-engine-demos/action_observations_map/";
  expect_same_dump("mrpt_ref_graphslam_range_030_bearing_015.txt",
                   dump_rawlog(require_file(dir + "range_030_bearing_015.rawlog")));
  expect_same_dump("mrpt_ref_graphslam_simul.txt", dump_rawlog(require_file(dir + "simul.rawlog")));
}

TEST(MrptPackageFiles, SyntheticSensorsWrittenByLibmrpt) {
  expect_same_dump("mrpt_ref_synthetic_sensors.txt",
                   dump_rawlog(kData + "mrpt_synthetic_sensors.rawlog"));
}

TEST(MrptPackageFiles, SyntheticSimplemapWithParticlesAndSog) {
  expect_same_dump("mrpt_ref_synthetic_pdfs.txt",
                   dump_simplemap(kData + "mrpt_synthetic_pdfs.simplemap.gz"));
}

}  // namespace
}  // namespace rove
