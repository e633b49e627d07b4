// Reference generator for rove's MRPT readers (links libmrpt 2.5).
//
//   rove_mrpt_obs_reference dump FILE        > reference.txt
//   rove_mrpt_obs_reference synthetic DIR
//   rove_mrpt_obs_reference velodyne-cloud FILE > cloud.txt
//   rove_mrpt_obs_reference synthetic-velodyne DIR
//
// `dump` reads a .rawlog or .simplemap(.gz) with libmrpt and prints, per
// observation and action, the values rove must read identically (see the
// line formats below); the first and last kFull entries are printed in
// full, every entry contributes to the per-class summary lines. `synthetic`
// writes small MRPT files exercising the classes and fields the shipped
// datasets do not (point clouds in Velodyne scans, GNSS message maps, gray
// and 16-bit images, particle and SOG pose PDFs, range-image layers), and
// their dumps next to them. `velodyne-cloud` decodes every Velodyne scan of
// a rawlog with generatePointCloud() (default parameters) and prints, per
// scan, a line "scan K N SX SY SZ SI" (its index among the scans, the point
// count, the sums of x, y, z and intensity) and every 16th point as
// "I X Y Z INTENSITY".
// `synthetic-velodyne` writes Velodyne scans the shipped data lacks: a
// VLP-16 and an HDL-32E with calibrations whose every correction is not
// zero, and a VLP-16 in dual-return mode, from pseudo-random returns.

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPose3DPDFParticles.h>
#include <mrpt/poses/CPose3DPDFSOG.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/poses/CPosePDFParticles.h>
#include <mrpt/poses/CPosePDFSOG.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace mrpt;

namespace {

constexpr int kFull = 3;

std::uint64_t ticks(const mrpt::Clock::time_point& t) {
  return static_cast<std::uint64_t>(t.time_since_epoch().count());
}

// FNV-1a over bytes: a checksum both sides compute the same way.
std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = 1469598103934665603ULL) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ULL;
  }
  return h;
}

void print_pose(const poses::CPose3D& p) {
  std::printf(" %.17g %.17g %.17g %.17g %.17g %.17g", p.x(), p.y(), p.z(), p.yaw(), p.pitch(),
              p.roll());
}

struct Summary {
  std::size_t count = 0;
  double sum = 0.0;          // a class-specific sum over all entries
  std::uint64_t hash = 1469598103934665603ULL;
};

std::map<std::string, Summary> g_summary;

void dump_camera(const img::TCamera& c) {
  std::printf(" cam %u %u %.17g %.17g %.17g %.17g", c.ncols, c.nrows, c.fx(), c.fy(), c.cx(),
              c.cy());
  // MRPT ignores the coefficients when the model is `none`.
  const bool used = c.distortion != img::DistortionModel::none;
  for (int k = 0; k < 5; ++k) std::printf(" %.17g", used ? c.dist[k] : 0.0);
}

// Sum of all image bytes and a few samples (channel 0..n-1 of pixels
// (0,0), (w/2,h/2), (w-1,h-1)) in MRPT's channel order (B, G, R).
void dump_image(const char* tag, const img::CImage& im) {
  const unsigned w = im.getWidth(), h = im.getHeight(), ch = im.getChannelCount();
  const std::size_t bpp = im.getPixelDepth() == img::PixelDepth::D16U ? 2 : 1;
  std::uint64_t sum = 0;
  for (unsigned v = 0; v < h; ++v) {
    const auto* row = im.ptrLine<std::uint8_t>(v);
    for (std::size_t i = 0; i < std::size_t{w} * ch * bpp; ++i) sum += row[i];
  }
  std::printf(" %s %u %u %u %zu %" PRIu64, tag, w, h, ch, bpp, sum);
  const unsigned us[3] = {0, w / 2, w - 1}, vs[3] = {0, h / 2, h - 1};
  for (int s = 0; s < 3 && w > 0 && h > 0; ++s) {
    const auto* px = im.ptrLine<std::uint8_t>(vs[s]) + std::size_t{us[s]} * ch * bpp;
    for (std::size_t c = 0; c < ch * bpp; ++c) std::printf(" %u", px[c]);
  }
}

void dump_observation(int k, const obs::CObservation& o, bool full) {
  const std::string cls = o.GetRuntimeClass()->className;
  Summary& S = g_summary[cls];
  ++S.count;
  if (full) std::printf("O %d %s L=%s t=%" PRIu64, k, cls.c_str(), o.sensorLabel.c_str(), ticks(o.timestamp));
  poses::CPose3D sp;
  o.getSensorPose(sp);
  if (auto s = dynamic_cast<const obs::CObservation2DRangeScan*>(&o)) {
    double sum = 0;
    for (size_t i = 0; i < s->getScanSize(); ++i) sum += s->getScanRange(i);
    S.sum += sum;
    if (full) {
      print_pose(sp);
      std::printf(" n=%zu %.9g %.9g %.17g", s->getScanSize(), s->aperture, s->maxRange, sum);
      for (size_t i = 0; i < std::min<size_t>(3, s->getScanSize()); ++i)
        std::printf(" %.9g %d", s->getScanRange(i), int(s->getScanRangeValidity(i)));
    }
  } else if (auto b = dynamic_cast<const obs::CObservationBearingRange*>(&o)) {
    double sum = 0;
    for (auto& m : b->sensedData) sum += m.range + m.yaw + m.pitch + m.landmarkID;
    S.sum += sum;
    if (full) {
      print_pose(sp);
      std::printf(" n=%zu %.9g %.9g %.9g %.9g %.17g", b->sensedData.size(), b->minSensorDistance,
                  b->maxSensorDistance, b->fieldOfView_yaw, b->fieldOfView_pitch, sum);
      for (size_t i = 0; i < std::min<size_t>(2, b->sensedData.size()); ++i) {
        const auto& m = b->sensedData[i];
        std::printf(" %d %.9g %.9g %.9g", m.landmarkID, m.range, m.yaw, m.pitch);
      }
    }
  } else if (auto r = dynamic_cast<const obs::CObservationBeaconRanges*>(&o)) {
    double sum = 0;
    for (auto& m : r->sensedData) sum += m.sensedDistance + m.beaconID;
    S.sum += sum;
    if (full) {
      std::printf(" n=%zu %.9g %.9g %.9g %.17g aux %.17g %.17g %.17g", r->sensedData.size(),
                  r->minSensorDistance, r->maxSensorDistance, r->stdError, sum,
                  r->auxEstimatePose.x(), r->auxEstimatePose.y(), r->auxEstimatePose.phi());
    }
  } else if (auto c = dynamic_cast<const obs::CObservationComment*>(&o)) {
    const std::uint64_t h = fnv1a(c->text.data(), c->text.size());
    S.hash = fnv1a(&h, sizeof h, S.hash);
    if (full) std::printf(" len=%zu hash=%" PRIu64, c->text.size(), h);
  } else if (auto g = dynamic_cast<const obs::CObservationGPS*>(&o)) {
    if (full) print_pose(sp);
    if (g->hasMsgClass<obs::gnss::Message_NMEA_GGA>()) {
      const auto& f = g->getMsgByClass<obs::gnss::Message_NMEA_GGA>().fields;
      S.sum += f.latitude_degrees + f.longitude_degrees + f.altitude_meters;
      if (full)
        std::printf(" GGA %u %u %.17g %.17g %.17g %u %.17g %u %.9g %.17g", f.UTCTime.hour,
                    f.UTCTime.minute, f.UTCTime.sec, f.latitude_degrees, f.longitude_degrees,
                    f.fix_quality, f.altitude_meters, f.satellitesUsed, f.HDOP,
                    f.geoidal_distance);
    }
    if (g->hasMsgClass<obs::gnss::Message_NMEA_RMC>()) {
      const auto& f = g->getMsgByClass<obs::gnss::Message_NMEA_RMC>().fields;
      S.sum += f.latitude_degrees + f.speed_knots;
      if (full)
        std::printf(" RMC %u %u %.17g %d %.17g %.17g %.17g %.17g", f.UTCTime.hour,
                    f.UTCTime.minute, f.UTCTime.sec, int(f.validity_char), f.latitude_degrees,
                    f.longitude_degrees, f.speed_knots, f.direction_degrees);
    }
  } else if (auto v = dynamic_cast<const obs::CObservationVelodyneScan*>(&o)) {
    std::uint64_t h = 1469598103934665603ULL;
    for (const auto& p : v->scan_packets) h = fnv1a(&p, sizeof p, h);
    S.hash = fnv1a(&h, sizeof h, S.hash);
    if (full) {
      print_pose(sp);
      std::printf(" %.17g %.17g packets=%zu hash=%" PRIu64 " calib=%zu", v->minRange, v->maxRange,
                  v->scan_packets.size(), h, v->calibration.laser_corrections.size());
      if (!v->scan_packets.empty()) {
        const auto& p0 = v->scan_packets.front();
        const auto& pl = v->scan_packets.back();
        std::printf(" p0 %u %u %u %u %u %u %u", p0.blocks[0].header(), p0.blocks[0].rotation(),
                    p0.blocks[0].laser_returns[0].distance(),
                    p0.blocks[0].laser_returns[0].intensity(), p0.gps_timestamp(),
                    p0.laser_return_mode, p0.velodyne_model_ID);
        std::printf(" pl %u %u %u", pl.blocks[11].rotation(),
                    pl.blocks[11].laser_returns[31].distance(), pl.gps_timestamp());
      }
      for (const auto& c : v->calibration.laser_corrections) {
        std::printf(" %.17g %.17g", c.verticalCorrection, c.sinVertCorrection);
        break;
      }
      const auto& pc = v->point_cloud;
      double sum = 0;
      for (size_t i = 0; i < pc.size(); ++i) sum += double(pc.x[i]) + pc.y[i] + pc.z[i] + pc.intensity[i];
      std::printf(" pc %zu %.17g %zu %zu %zu %zu %d", pc.size(), sum, pc.timestamp.size(),
                  pc.azimuth.size(), pc.laser_id.size(), pc.pointsForLaserID.size(),
                  int(v->has_satellite_timestamp));
      if (!pc.timestamp.empty()) std::printf(" %" PRIu64, ticks(pc.timestamp.back()));
      if (!pc.azimuth.empty()) std::printf(" %.9g %d", pc.azimuth.back(), pc.laser_id.back());
      for (const auto& ids : pc.pointsForLaserID) {
        std::printf(" [%zu", ids.size());
        for (auto i : ids) std::printf(" %" PRIu64, i);
        std::printf("]");
      }
    }
  } else if (auto q = dynamic_cast<const obs::CObservationRotatingScan*>(&o)) {
    double sum = 0;
    for (int r = 0; r < q->rangeImage.rows(); ++r)
      for (int c = 0; c < q->rangeImage.cols(); ++c) sum += q->rangeImage(r, c);
    S.sum += sum;
    if (full) {
      print_pose(sp);
      std::printf(" %u %u %.17g %.17g %.17g %.17g %s %.17g %.17g %" PRIu64 " %d sum=%.17g",
                  q->rowCount, q->columnCount, q->rangeResolution, q->startAzimuth,
                  q->azimuthSpan, q->sweepDuration, q->lidarModel.c_str(), q->minRange,
                  q->maxRange, ticks(q->originalReceivedTimestamp), int(q->has_satellite_timestamp),
                  sum);
      double isum = 0;
      for (int r = 0; r < q->intensityImage.rows(); ++r)
        for (int c = 0; c < q->intensityImage.cols(); ++c) isum += q->intensityImage(r, c);
      std::printf(" int %d %.17g layers %zu", int(q->intensityImage.rows() * q->intensityImage.cols()),
                  isum, q->rangeOtherLayers.size());
      for (const auto& [name, m] : q->rangeOtherLayers) {
        double ls = 0;
        for (int r = 0; r < m.rows(); ++r)
          for (int c = 0; c < m.cols(); ++c) ls += m(r, c);
        std::printf(" %s %.17g", name.c_str(), ls);
      }
      if (q->rangeImage.size() > 0) {
        const int r = q->rangeImage.rows() - 1, c = q->rangeImage.cols() / 2;
        std::printf(" sample %d %d %u %u", r, c, q->rangeImage(0, 0), q->rangeImage(r, c));
      }
    }
  } else if (auto d = dynamic_cast<const obs::CObservation3DRangeScan*>(&o)) {
    double psum = 0;
    for (size_t i = 0; i < d->points3D_x.size(); ++i)
      psum += double(d->points3D_x[i]) + d->points3D_y[i] + d->points3D_z[i];
    S.sum += psum;
    if (full) {
      print_pose(sp);
      std::printf(" %.9g %.9g %.9g %d %d", d->maxRange, d->stdError, d->rangeUnits,
                  int(d->range_is_depth), int(d->intensityImageChannel));
      std::printf(" pts %zu %.17g", d->points3D_x.size(), psum);
      if (!d->points3D_x.empty()) {
        const size_t m = d->points3D_x.size() / 2;
        std::printf(" %.9g %.9g %.9g", d->points3D_x[m], d->points3D_y[m], d->points3D_z[m]);
        std::uint64_t iu = 0, iv = 0;
        for (size_t i = 0; i < d->points3D_idxs_x.size(); ++i) iu += d->points3D_idxs_x[i];
        for (size_t i = 0; i < d->points3D_idxs_y.size(); ++i) iv += d->points3D_idxs_y[i];
        std::printf(" %zu %" PRIu64 " %" PRIu64, d->points3D_idxs_x.size(), iu, iv);
      }
      if (d->hasRangeImage) {
        std::uint64_t rs = 0;
        for (int r = 0; r < d->rangeImage.rows(); ++r)
          for (int c = 0; c < d->rangeImage.cols(); ++c) rs += d->rangeImage(r, c);
        const int r = d->rangeImage.rows() / 2, c = d->rangeImage.cols() / 3;
        std::printf(" range %d %d %" PRIu64 " %d %d %u", int(d->rangeImage.rows()),
                    int(d->rangeImage.cols()), rs, r, c, d->rangeImage(r, c));
      }
      if (d->hasIntensityImage) dump_image("int", d->intensityImage);
      if (d->hasConfidenceImage) dump_image("conf", d->confidenceImage);
      dump_camera(d->cameraParams);
      dump_camera(d->cameraParamsIntensity);
      std::printf(" rel");
      print_pose(d->relativePoseIntensityWRTDepth);
      std::printf(" layers %zu", d->rangeImageOtherLayers.size());
      for (const auto& [name, m] : d->rangeImageOtherLayers) {
        std::uint64_t ls = 0;
        for (int r = 0; r < m.rows(); ++r)
          for (int c = 0; c < m.cols(); ++c) ls += m(r, c);
        // MRPT 2.5.8 writes a layer's cols then rows but reads rows then
        // cols, transposing its shape; print the shape as written.
        std::printf(" %s %d %d %" PRIu64, name.c_str(), int(m.cols()), int(m.rows()), ls);
      }
    }
  } else if (full) {
    print_pose(sp);
  }
  if (full) std::printf("\n");
}

void dump_action(int k, const obs::CAction& a, bool full) {
  const std::string cls = a.GetRuntimeClass()->className;
  Summary& S = g_summary[cls];
  ++S.count;
  if (auto m = dynamic_cast<const obs::CActionRobotMovement3D*>(&a)) {
    S.sum += m->poseChange.mean.x() + m->poseChange.mean.y() + m->poseChange.mean.z() +
             m->poseChange.cov.sum();
    if (!full) return;
    std::printf("A %d %s t=%" PRIu64 " %d", k, cls.c_str(), ticks(a.timestamp),
                int(m->estimationMethod));
    for (int i = 0; i < 6; ++i) std::printf(" %d", int(m->hasVelocities[i]));
    print_pose(m->poseChange.mean);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) std::printf(" %.17g", m->poseChange.cov(i, j));
    for (int i = 0; i < 6; ++i) {
      if (m->hasVelocities[i]) {
        std::printf(" %.9g", m->velocities[i]);
      } else {
        std::printf(" -");
      }
    }
    std::printf("\n");
  } else if (auto m2 = dynamic_cast<const obs::CActionRobotMovement2D*>(&a)) {
    const auto& o = m2->rawOdometryIncrementReading;
    S.sum += o.x() + o.y() + o.phi();
    if (!full) return;
    std::printf("A %d %s t=%" PRIu64 " %.17g %.17g %.17g\n", k, cls.c_str(), ticks(a.timestamp),
                o.x(), o.y(), o.phi());
  }
}

void dump_pose_pdf(int k, const poses::CPose3DPDF& pdf) {
  const std::string cls = pdf.GetRuntimeClass()->className;
  ++g_summary[cls].count;
  poses::CPose3D mean;
  pdf.getMean(mean);
  std::printf("P %d %s", k, cls.c_str());
  print_pose(mean);
  if (auto p = dynamic_cast<const poses::CPose3DPDFParticles*>(&pdf)) {
    std::printf(" n=%zu", p->size());
    for (size_t i = 0; i < p->size(); ++i) {
      const auto& t = p->m_particles[i].d;
      std::printf(" %.17g %.17g %.17g %.17g %.17g %.17g %.17g", p->m_particles[i].log_w, t.x, t.y,
                  t.z, t.yaw, t.pitch, t.roll);
    }
  } else if (auto s = dynamic_cast<const poses::CPose3DPDFSOG*>(&pdf)) {
    std::printf(" n=%zu", s->size());
    for (const auto& m : *s) {
      std::printf(" %.17g", m.log_w);
      print_pose(m.val.mean);
      for (int i = 0; i < 6; ++i) std::printf(" %.17g", m.val.cov(i, i));
      std::printf(" %.17g", m.val.cov(0, 5));
    }
  } else if (auto g = dynamic_cast<const poses::CPose3DPDFGaussian*>(&pdf)) {
    for (int i = 0; i < 6; ++i) std::printf(" %.17g", g->cov(i, i));
    std::printf(" %.17g", g->cov(0, 5));
  }
  std::printf("\n");
}

void print_summary() {
  for (const auto& [cls, s] : g_summary)
    std::printf("SUM %s %zu %.17g %" PRIu64 "\n", cls.c_str(), s.count, s.sum, s.hash);
}

int dump(const char* path) {
  io::CFileGZInputStream f(path);
  auto ar = serialization::archiveFrom(f);
  std::vector<serialization::CSerializable::Ptr> objs;
  for (;;) {
    serialization::CSerializable::Ptr o;
    try {
      ar >> o;
    } catch (const std::exception&) {
      break;
    }
    objs.push_back(o);
  }
  std::printf("# libmrpt 2.5.8 reading %s: %zu top-level objects\n", path, objs.size());
  const int n = static_cast<int>(objs.size());
  for (int k = 0; k < n; ++k) {
    const bool full = k < kFull || k >= n - kFull;
    const auto& o = objs[k];
    if (auto ac = std::dynamic_pointer_cast<obs::CActionCollection>(o)) {
      for (const auto& a : *ac) dump_action(k, *a, full);
    } else if (auto sf = std::dynamic_pointer_cast<obs::CSensoryFrame>(o)) {
      for (const auto& x : *sf) dump_observation(k, *x, full);
    } else if (auto ob = std::dynamic_pointer_cast<obs::CObservation>(o)) {
      dump_observation(k, *ob, full);
    } else if (auto sm = std::dynamic_pointer_cast<maps::CSimpleMap>(o)) {
      int i = 0;
      for (const auto& kf : *sm) {
        const bool kfull = i < kFull || i >= int(sm->size()) - kFull;
        if (kfull) dump_pose_pdf(i, *kf.pose);
        for (const auto& x : *kf.sf) dump_observation(i, *x, kfull);
        ++i;
      }
    }
  }
  print_summary();
  return 0;
}

// ---- synthetic files -------------------------------------------------------

mrpt::Clock::time_point at_ticks(std::uint64_t t) {
  return mrpt::Clock::time_point(mrpt::Clock::duration(t));
}

void write_synthetic_rawlog(const std::string& path) {
  img::CImage::DISABLE_JPEG_COMPRESSION(true);
  io::CFileOutputStream f(path);
  auto ar = serialization::archiveFrom(f);

  // A Velodyne scan with two packets and a decoded point cloud.
  auto v = std::make_shared<obs::CObservationVelodyneScan>();
  v->timestamp = at_ticks(133000000000000000ULL);
  v->sensorLabel = "VELO";
  v->sensorPose = poses::CPose3D(0.1, 0.2, 1.5, 0.3, 0.0, 0.0);
  v->scan_packets.resize(2);
  for (size_t p = 0; p < 2; ++p) {
    auto* bytes = reinterpret_cast<std::uint8_t*>(&v->scan_packets[p]);
    for (size_t i = 0; i < sizeof(v->scan_packets[p]); ++i) bytes[i] = std::uint8_t(i * 7 + p * 13);
  }
  v->calibration.laser_corrections.resize(2);
  v->calibration.laser_corrections[1].verticalCorrection = 0.25;
  v->calibration.laser_corrections[1].sinVertCorrection = 0.2474039592545229;
  auto& pc = v->point_cloud;
  pc.x = {1.0f, 2.0f, 3.0f};
  pc.y = {-1.0f, 0.5f, 0.25f};
  pc.z = {0.125f, 0.0f, -2.0f};
  pc.intensity = {10, 200, 255};
  pc.timestamp = {at_ticks(133000000000000001ULL), at_ticks(133000000000000002ULL),
                  at_ticks(133000000000000003ULL)};
  pc.azimuth = {0.5f, 1.5f, 2.5f};
  pc.laser_id = {0, 1, 1};
  pc.pointsForLaserID = {{0}, {1, 2}};
  v->has_satellite_timestamp = true;
  ar << *v;

  // A GNSS observation with GGA and RMC messages (version 11 message map).
  auto g = std::make_shared<obs::CObservationGPS>();
  g->timestamp = at_ticks(133000000010000000ULL);
  g->originalReceivedTimestamp = at_ticks(133000000010000005ULL);
  g->sensorLabel = "GNSS";
  g->sensorPose = poses::CPose3D(0.5, 0, 1.0, 0, 0, 0);
  g->has_satellite_timestamp = true;
  obs::gnss::Message_NMEA_GGA gga;
  gga.fields.UTCTime.hour = 12;
  gga.fields.UTCTime.minute = 34;
  gga.fields.UTCTime.sec = 56.25;
  gga.fields.latitude_degrees = 36.714459075;
  gga.fields.longitude_degrees = -4.478958828;
  gga.fields.fix_quality = 4;
  gga.fields.altitude_meters = 38.8887;
  gga.fields.geoidal_distance = 51.5;
  gga.fields.satellitesUsed = 9;
  gga.fields.thereis_HDOP = true;
  gga.fields.HDOP = 0.75f;
  g->setMsg(gga);
  obs::gnss::Message_NMEA_RMC rmc;
  rmc.fields.UTCTime.hour = 12;
  rmc.fields.UTCTime.minute = 34;
  rmc.fields.UTCTime.sec = 56.5;
  rmc.fields.validity_char = 'A';
  rmc.fields.latitude_degrees = 36.7145;
  rmc.fields.longitude_degrees = -4.479;
  rmc.fields.speed_knots = 3.5;
  rmc.fields.direction_degrees = 271.25;
  rmc.fields.date_day = 21;
  rmc.fields.date_month = 11;
  rmc.fields.date_year = 8;
  rmc.fields.magnetic_dir = -1.5;
  rmc.fields.positioning_mode = 'D';
  g->setMsg(rmc);
  ar << *g;

  // A 3D range scan: 4x3 range image, 16-bit gray intensity, 8-bit
  // confidence, points with pixel indices, one extra layer.
  auto d = std::make_shared<obs::CObservation3DRangeScan>();
  d->timestamp = at_ticks(133000000020000000ULL);
  d->sensorLabel = "TOF";
  d->sensorPose = poses::CPose3D(0, 0, 0.8, 0.1, 0.2, 0.3);
  d->maxRange = 6.0f;
  d->stdError = 0.02f;
  d->rangeUnits = 0.0005f;
  d->range_is_depth = false;
  d->intensityImageChannel = obs::CObservation3DRangeScan::CH_IR;
  d->hasRangeImage = true;
  d->rangeImage_setSize(3, 4);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) d->rangeImage(r, c) = std::uint16_t(1000 + 100 * r + c);
  d->hasPoints3D = true;
  d->resizePoints3DVectors(2);
  d->points3D_x = {1.0f, 1.5f};
  d->points3D_y = {0.25f, -0.25f};
  d->points3D_z = {0.5f, -0.125f};
  d->points3D_idxs_x = {1, 3};
  d->points3D_idxs_y = {0, 2};
  d->hasIntensityImage = true;
  d->intensityImage.resize(4, 3, img::CH_GRAY, img::PixelDepth::D16U);
  for (unsigned v2 = 0; v2 < 3; ++v2)
    for (unsigned u = 0; u < 4; ++u)
      d->intensityImage.ptrLine<std::uint16_t>(v2)[u] = std::uint16_t(300 * v2 + u + 7);
  d->hasConfidenceImage = true;
  d->confidenceImage.resize(4, 3, img::CH_GRAY);
  for (unsigned v2 = 0; v2 < 3; ++v2)
    for (unsigned u = 0; u < 4; ++u) *d->confidenceImage.ptr<std::uint8_t>(u, v2) = std::uint8_t(10 * v2 + u);
  d->cameraParams.ncols = 4;
  d->cameraParams.nrows = 3;
  d->cameraParams.setIntrinsicParamsFromValues(3.0, 3.5, 1.5, 1.0);
  d->cameraParams.dist[0] = 0.01;
  d->cameraParams.dist[4] = -0.002;
  d->cameraParams.distortion = img::DistortionModel::plumb_bob;
  d->cameraParamsIntensity = d->cameraParams;
  d->cameraParamsIntensity.distortion = img::DistortionModel::none;
  d->relativePoseIntensityWRTDepth = poses::CPose3D(0.025, 0, 0, -M_PI / 2, 0, -M_PI / 2);
  d->rangeImageOtherLayers["second"].resize(3, 4);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) d->rangeImageOtherLayers["second"](r, c) = std::uint16_t(5 * r + c);
  ar << *d;

  // A rotating scan with intensity and one extra layer.
  auto q = std::make_shared<obs::CObservationRotatingScan>();
  q->timestamp = at_ticks(133000000030000000ULL);
  q->sensorLabel = "ROT";
  q->rowCount = 2;
  q->columnCount = 3;
  q->rangeResolution = 0.005;
  q->startAzimuth = -1.0;
  q->azimuthSpan = 2.0;
  q->sweepDuration = 0.1;
  q->lidarModel = "TEST";
  q->minRange = 0.5;
  q->maxRange = 80.0;
  q->sensorPose = poses::CPose3D(0, 0, 2.0, 0, 0, 0);
  q->originalReceivedTimestamp = at_ticks(133000000030000001ULL);
  q->rangeImage.resize(2, 3);
  q->intensityImage.resize(2, 3);
  q->rangeOtherLayers["strongest"].resize(2, 3);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      q->rangeImage(r, c) = std::uint16_t(100 * r + c + 1);
      q->intensityImage(r, c) = std::uint8_t(50 * r + c);
      q->rangeOtherLayers["strongest"](r, c) = std::uint16_t(7 * r + c);
    }
  ar << *q;

  // A 3D movement inside an action collection.
  obs::CActionCollection acts;
  obs::CActionRobotMovement3D mv;
  mv.timestamp = at_ticks(133000000040000000ULL);
  mv.estimationMethod = obs::CActionRobotMovement3D::emVisualOdometry;
  mv.poseChange.mean = poses::CPose3D(0.5, 0.1, 0.02, 0.05, 0.01, -0.02);
  mv.poseChange.cov.setIdentity();
  mv.poseChange.cov *= 1e-3;
  mv.poseChange.cov(0, 1) = mv.poseChange.cov(1, 0) = 1e-4;
  mv.hasVelocities = {true, true, true, false, false, true};
  for (int i = 0; i < 6; ++i) mv.velocities[i] = 0.1f * float(i + 1);
  acts.insert(mv);
  ar << acts;
}

void write_synthetic_pdfs(const std::string& path) {
  io::CFileOutputStream f(path);
  auto ar = serialization::archiveFrom(f);
  poses::CPosePDFParticles p2(3);
  for (size_t i = 0; i < 3; ++i) {
    p2.m_particles[i].d = math::TPose2D(1.0 + i, -0.5 * i, 0.1 * i);
    p2.m_particles[i].log_w = -0.5 * i;
  }
  ar << p2;
  poses::CPosePDFSOG s2(2);
  s2[0].mean = poses::CPose2D(1, 2, 0.3);
  s2[0].cov.setIdentity();
  s2[0].log_w = -0.1;
  s2[1].mean = poses::CPose2D(-1, 0.5, -2.0);
  s2[1].cov.setIdentity();
  s2[1].cov *= 0.5;
  s2[1].cov(0, 2) = s2[1].cov(2, 0) = 0.01;
  s2[1].log_w = -2.0;
  ar << s2;
}

void write_synthetic_simplemap(const std::string& path) {
  maps::CSimpleMap sm;
  auto sf = std::make_shared<obs::CSensoryFrame>();
  auto scan = std::make_shared<obs::CObservation2DRangeScan>();
  scan->resizeScan(3);
  for (int i = 0; i < 3; ++i) scan->setScanRange(i, 1.0f + i), scan->setScanRangeValidity(i, true);
  scan->aperture = 1.0f;
  scan->sensorLabel = "LASER";
  sf->insert(scan);

  auto part = std::make_shared<poses::CPose3DPDFParticles>(2);
  part->m_particles[0].d = math::TPose3D(1, 2, 3, 0.1, 0.2, 0.3);
  part->m_particles[0].log_w = 0.0;
  part->m_particles[1].d = math::TPose3D(1.5, 2.5, 3.5, 0.15, 0.1, -0.3);
  part->m_particles[1].log_w = -1.0;
  sm.insert(part, sf);

  auto sog = std::make_shared<poses::CPose3DPDFSOG>(2);
  auto it = sog->begin();
  it->log_w = -0.25;
  it->val.mean = poses::CPose3D(0, 1, 0, 0.5, 0, 0);
  it->val.cov.setIdentity();
  it->val.cov(0, 5) = it->val.cov(5, 0) = 0.05;
  ++it;
  it->log_w = -1.5;
  it->val.mean = poses::CPose3D(2, 1, 0.5, -0.5, 0.1, 0);
  it->val.cov.setIdentity();
  it->val.cov *= 2.0;
  sm.insert(sog, sf);

  auto gauss = std::make_shared<poses::CPose3DPDFGaussian>();
  gauss->mean = poses::CPose3D(3, -1, 0, 1.0, 0, 0);
  gauss->cov.setIdentity();
  gauss->cov *= 0.01;
  sm.insert(gauss, sf);

  io::CFileGZOutputStream f(path);
  auto ar = serialization::archiveFrom(f);
  ar << sm;
}

// Pseudo-random bytes (SplitMix64), the same on every platform.
struct Mix {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
};

// A calibration of n lasers with the nominal elevations of a VLP-16 (n = 16)
// or HDL-32E (n = 32), degrees, and small corrections of every kind.
obs::VelodyneCalibration synthetic_calibration(int n) {
  obs::VelodyneCalibration c;
  c.laser_corrections.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    auto& l = c.laser_corrections[static_cast<std::size_t>(i)];
    l.verticalCorrection = n == 16 ? (i % 2 == 0 ? -15.0 + i : i) + 0.01 * i
                                   : -30.67 + 1.33 * (i / 2 + (i % 2) * 16) + 0.02 * (i % 3);
    l.azimuthCorrection = 0.3 * (i % 5) - 0.6;
    l.distanceCorrection = 0.01 * i - 0.05;
    l.verticalOffsetCorrection = 0.002 * i + 0.01;
    l.horizontalOffsetCorrection = 0.003 * (i % 4) - 0.004;
    l.sinVertCorrection = std::sin(l.verticalCorrection * M_PI / 180.0);
    l.cosVertCorrection = std::cos(l.verticalCorrection * M_PI / 180.0);
    l.sinVertOffsetCorrection = l.verticalOffsetCorrection * l.sinVertCorrection;
    l.cosVertOffsetCorrection = l.verticalOffsetCorrection * l.cosVertCorrection;
  }
  return c;
}

// A scan of `packets` packets: azimuths from `azimuth0` (hundredths of a
// degree) advancing `step` per block (per pair of blocks in dual mode).
std::shared_ptr<obs::CObservationVelodyneScan> synthetic_scan(std::uint8_t model, std::uint8_t mode, int packets,
                                                               int azimuth0, int step, std::uint64_t seed) {
  auto v = std::make_shared<obs::CObservationVelodyneScan>();
  v->timestamp = at_ticks(133000000000000000ULL + seed);
  v->sensorLabel = "VELO";
  v->minRange = 1.0;
  v->maxRange = 120.0;
  v->calibration = synthetic_calibration(model == 0x21 ? 32 : 16);
  v->scan_packets.resize(static_cast<std::size_t>(packets));
  Mix mix{seed};
  int azimuth = azimuth0;
  for (int p = 0; p < packets; ++p) {
    auto* bytes = reinterpret_cast<std::uint8_t*>(&v->scan_packets[static_cast<std::size_t>(p)]);
    for (int b = 0; b < 12; ++b) {
      std::uint8_t* blk = bytes + 100 * b;
      blk[0] = 0xFF, blk[1] = 0xEE;
      if (mode == 0x39 && b % 2 == 1) {
        azimuth -= step;  // the second block of a pair repeats the azimuth
      }
      const int a = ((azimuth % 36000) + 36000) % 36000;
      blk[2] = std::uint8_t(a & 0xFF), blk[3] = std::uint8_t(a >> 8);
      azimuth += step;
      for (int r = 0; r < 32; ++r) {
        const std::uint64_t x = mix.next();
        int d = int(x % 60000);
        if (x % 23 == 0) d = 0;
        if (x % 29 == 0) d = int(x % 500);
        blk[4 + 3 * r] = std::uint8_t(d & 0xFF), blk[5 + 3 * r] = std::uint8_t(d >> 8);
        blk[6 + 3 * r] = std::uint8_t(x >> 40);
      }
    }
    bytes[1200] = bytes[1201] = bytes[1202] = bytes[1203] = 0;
    bytes[1204] = mode;
    bytes[1205] = model;
  }
  return v;
}

// DIR/mrpt_synthetic_velodyne.rawlog (the three scans) and
// DIR/mrpt_synthetic_velodyne_uncalibrated.rawlog (a VLP-16 scan without
// its calibration, which cannot be decoded).
void write_synthetic_velodyne(const std::string& dir) {
  {
    io::CFileOutputStream f(dir + "/mrpt_synthetic_velodyne.rawlog");
    auto ar = serialization::archiveFrom(f);
    ar << *synthetic_scan(0x22, 0x37, 6, 35500, 20, 1);
    ar << *synthetic_scan(0x21, 0x37, 4, 1000, 15, 2);
    ar << *synthetic_scan(0x22, 0x39, 6, 18000, 40, 3);
  }
  io::CFileOutputStream f(dir + "/mrpt_synthetic_velodyne_uncalibrated.rawlog");
  auto ar = serialization::archiveFrom(f);
  auto v = synthetic_scan(0x22, 0x37, 2, 100, 20, 4);
  v->calibration.clear();
  ar << *v;
}

int velodyne_clouds(const char* path) {
  io::CFileGZInputStream f(path);
  auto ar = serialization::archiveFrom(f);
  std::printf("# libmrpt 2.5.8 generatePointCloud() of the Velodyne scans in %s\n", path);
  int k = 0;  // Velodyne scans seen
  const auto print = [&](const obs::CObservation& o) {
    const auto* v = dynamic_cast<const obs::CObservationVelodyneScan*>(&o);
    if (v == nullptr) return;
    obs::CObservationVelodyneScan copy(*v);
    copy.generatePointCloud();
    const auto& pc = copy.point_cloud;
    double sx = 0, sy = 0, sz = 0, si = 0;
    for (std::size_t i = 0; i < pc.size(); ++i) sx += pc.x[i], sy += pc.y[i], sz += pc.z[i], si += pc.intensity[i];
    std::printf("scan %d %zu %.17g %.17g %.17g %.17g\n", k, pc.size(), sx, sy, sz, si);
    for (std::size_t i = 0; i < pc.size(); i += 16) {
      std::printf("%zu %.9g %.9g %.9g %u\n", i, pc.x[i], pc.y[i], pc.z[i], unsigned(pc.intensity[i]));
    }
    ++k;
  };
  for (;;) {
    serialization::CSerializable::Ptr o;
    try {
      ar >> o;
    } catch (const std::exception&) {
      break;
    }
    if (auto sf = std::dynamic_pointer_cast<obs::CSensoryFrame>(o)) {
      for (const auto& x : *sf) print(*x);
    } else if (auto ob = std::dynamic_pointer_cast<obs::CObservation>(o)) {
      print(*ob);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Files written by MRPT 1.x use the bare class name, which MRPT 2.5 does
  // not register for this class.
  rtti::registerClassCustomName("CObservationRotatingScan",
                                CLASS_ID(obs::CObservationRotatingScan));
  if (argc == 3 && std::strcmp(argv[1], "dump") == 0) return dump(argv[2]);
  if (argc == 3 && std::strcmp(argv[1], "velodyne-cloud") == 0) return velodyne_clouds(argv[2]);
  if (argc == 3 && std::strcmp(argv[1], "synthetic-velodyne") == 0) {
    write_synthetic_velodyne(argv[2]);
    return 0;
  }
  if (argc == 3 && std::strcmp(argv[1], "synthetic") == 0) {
    const std::string dir = argv[2];
    write_synthetic_rawlog(dir + "/mrpt_synthetic_sensors.rawlog");
    write_synthetic_pdfs(dir + "/mrpt_synthetic_pose_pdfs.bin");
    write_synthetic_simplemap(dir + "/mrpt_synthetic_pdfs.simplemap.gz");
    return 0;
  }
  std::fprintf(stderr, "usage: %s dump FILE | synthetic DIR | velodyne-cloud FILE | synthetic-velodyne DIR\n", argv[0]);
  return 2;
}
