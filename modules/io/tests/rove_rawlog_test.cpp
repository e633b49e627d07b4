// rove's own rawlog format: round trips of every observation type, a frozen
// file written by format version 1, and malformed, truncated and hostile
// files (ParseError with file, offset and class; never a crash).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rawlog_reader.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/imu_observation.h"
#include "rove/obs/obs_registry.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/angle.h"
#include "rove/serialization/class_registry.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/memory_stream.h"

namespace rove {
namespace {

const std::string kData = std::string(ROVE_SOURCE_DIR) + "/modules/io/tests/data/";
const std::string kFrozen = kData + "rove_rawlog_v1_frozen.rawlog";

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("rove_rawlog_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

void stamp(Observation& o, const char* label, std::int64_t ns) {
  o.timestamp = Timestamp::from_ns(ns);
  o.sensor_label = label;
  o.T_robot_sensor = Pose3(0.1, -0.2, 0.3, 0.4, -0.5, 0.6);
}

// One observation of every type, with non-default values in every field.
std::vector<std::shared_ptr<const Observation>> sample_observations() {
  std::vector<std::shared_ptr<const Observation>> out;
  auto scan = std::make_shared<RangeScan2D>();
  stamp(*scan, "LASER", 1262304000123456700);
  scan->aperture = deg_to_rad(270.0);
  scan->right_to_left = false;
  scan->max_range = 30.0f;
  scan->set_ranges({1.0f, 2.5f, 0.0f, 29.0f, 31.0f});
  scan->intensity = {10, 20, 30, 40, 50};
  out.push_back(scan);

  auto rgbd = std::make_shared<RangeImage3D>();
  stamp(*rgbd, "KINECT", 1262304000223456700);
  rgbd->depth_camera = {4, 2, 5.0, 6.0, 1.5, 0.5, {0.1, -0.01, 0.001, 0.002, 0.0}};
  rgbd->depth = DepthImage::zeros_u16(4, 2, 5000.0);
  std::get<std::vector<std::uint16_t>>(rgbd->depth.values) = {0, 1, 2, 3, 4, 5, 6, 65535};
  rgbd->intensity = Image::zeros(4, 2, 3, PixelType::U8);
  rgbd->intensity->data[5] = 200;
  out.push_back(rgbd);

  auto odo = std::make_shared<OdometryObservation>();
  stamp(*odo, "ODOMETRY", 1262304000323456700);
  odo->odometry = Pose2(1.0, 2.0, 0.5);
  odo->encoder_ticks = EncoderTicks{-7, 12};
  odo->velocity = Twist2{0.3, 0.0, -0.1};
  out.push_back(odo);

  auto image = std::make_shared<ImageObservation>();
  stamp(*image, "CAMERA", 1262304000423456700);
  image->camera = {3, 2, 300.0, 300.0, 1.0, 0.5, {}};
  image->image = Image::zeros(3, 2, 1, PixelType::U16);
  image->image.data[3] = 0xAB;
  out.push_back(image);

  auto beacons = std::make_shared<BeaconRanges>();
  stamp(*beacons, "UWB", 1262304000523456700);
  beacons->readings = {{1, 3.5f, {0.1, 0.0, 0.2}}, {7, 12.25f, {-0.1, 0.0, 0.2}}};
  out.push_back(beacons);

  auto bearing = std::make_shared<BearingRange>();
  stamp(*bearing, "STEREO", 1262304000623456700);
  LandmarkMeasurement m;
  m.landmark_id = 3;
  m.range = 2.0f;
  m.yaw = 0.3f;
  m.covariance = Eigen::Matrix3d::Identity() * 0.01;
  bearing->measurements = {m};
  out.push_back(bearing);

  auto imu = std::make_shared<ImuObservation>();
  stamp(*imu, "IMU", 1262304000723456700);
  imu->angular_velocity = Eigen::Vector3d(0.01, -0.02, 0.3);
  imu->orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  out.push_back(imu);

  auto gps = std::make_shared<GpsObservation>();
  stamp(*gps, "GPS", 1262304000823456700);
  gps->latitude_deg = 36.8389;
  gps->longitude_deg = -2.4597;
  gps->fix_quality = GpsFixQuality::RtkFixed;
  gps->satellites = 11;
  gps->enu_position = Eigen::Vector3d(10.0, -3.0, 0.5);
  out.push_back(gps);
  return out;
}

std::shared_ptr<const ActionCollection> sample_actions(double dx) {
  auto move = std::make_shared<RobotMovement2D>(Pose2(dx, 0.01, 0.05), MotionModelOptions{});
  move->timestamp = Timestamp::from_ns(1262304000900000000);
  move->encoder_ticks = EncoderTicks{100, 101};
  auto ac = std::make_shared<ActionCollection>();
  ac->add(move);
  return ac;
}

// Layout #1 entries: frame, (actions, frame) × 2, frames holding every type.
std::vector<RawlogEntry> sample_layout1() {
  const auto obs = sample_observations();
  std::vector<RawlogEntry> entries;
  auto f0 = std::make_shared<SensoryFrame>();
  f0->add(obs[0]);
  f0->add(obs[2]);
  entries.emplace_back(std::shared_ptr<const SensoryFrame>(f0));
  entries.emplace_back(sample_actions(0.2));
  auto f1 = std::make_shared<SensoryFrame>();
  for (const auto& o : obs) f1->add(o);
  entries.emplace_back(std::shared_ptr<const SensoryFrame>(f1));
  entries.emplace_back(sample_actions(-0.1));
  entries.emplace_back(std::shared_ptr<const SensoryFrame>(std::make_shared<SensoryFrame>()));
  return entries;
}

bool entries_equal(const RawlogEntry& a, const RawlogEntry& b) {
  if (a.index() != b.index()) return false;
  if (auto* x = std::get_if<std::shared_ptr<const ActionCollection>>(&a)) {
    return **x == *std::get<std::shared_ptr<const ActionCollection>>(b);
  }
  if (auto* x = std::get_if<std::shared_ptr<const SensoryFrame>>(&a)) {
    return **x == *std::get<std::shared_ptr<const SensoryFrame>>(b);
  }
  return std::get<std::shared_ptr<const Observation>>(a)->equals(
      *std::get<std::shared_ptr<const Observation>>(b));
}

void expect_same_entries(const std::vector<RawlogEntry>& a, const std::vector<RawlogEntry>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(entries_equal(a[i], b[i])) << "entry " << i;
}

std::vector<std::byte> write_to_memory(const std::vector<RawlogEntry>& entries, RawlogLayout layout,
                                       RawlogMetadata metadata = {}) {
  auto out = std::make_unique<MemoryOutStream>("mem");
  auto* raw = out.get();
  RoveRawlogWriterOptions o;
  o.layout = layout;
  o.metadata = std::move(metadata);
  std::vector<std::byte> bytes;
  {
    RoveRawlogWriter w(std::move(out), o);
    for (const auto& e : entries) w.write(e);
    w.close();
    bytes = raw->data();
  }
  return bytes;
}

std::vector<RawlogEntry> read_from_memory(std::vector<std::byte> bytes,
                                          RoveRawlogReaderOptions options = {},
                                          std::uint64_t* skipped = nullptr) {
  RoveRawlogReader r(std::make_unique<MemoryInStream>(std::move(bytes), "mem.rawlog"), options);
  std::vector<RawlogEntry> out;
  while (auto e = r.next()) out.push_back(std::move(*e));
  if (skipped != nullptr) *skipped = r.skipped_entries();
  return out;
}

std::vector<std::byte> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  EXPECT_TRUE(f.good()) << "missing file " << path;
  std::vector<char> c((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<std::byte> b(c.size());
  std::memcpy(b.data(), c.data(), c.size());
  return b;
}

TEST(RoveRawlog, RoundTripLayout1PlainAndGzip) {
  const auto entries = sample_layout1();
  for (bool gzip : {false, true}) {
    const std::string path = temp_path(gzip ? "l1.rawlog.gz" : "l1.rawlog");
    RoveRawlogWriterOptions o;
    o.gzip = gzip;
    o.metadata = {{"source", "unit test"}, {"tool", "rove"}};
    save_rove_rawlog(path, entries, o);
    EXPECT_EQ(is_gzip_file(path), gzip);
    EXPECT_EQ(detect_rawlog_format(path), RawlogFormat::Rove);
    const RoveRawlog back = load_rove_rawlog(path);
    EXPECT_EQ(back.layout, RawlogLayout::ActionsSensoryFrames);
    EXPECT_EQ(back.metadata.at("source"), "unit test");
    expect_same_entries(entries, back.entries);
    // The same through the format-detecting reader.
    const AnyRawlog any = load_any_rawlog(path);
    EXPECT_EQ(any.format, RawlogFormat::Rove);
    expect_same_entries(entries, any.entries);
    std::filesystem::remove(path);
  }
}

TEST(RoveRawlog, RoundTripLayout2EveryObservationType) {
  std::vector<RawlogEntry> entries;
  for (const auto& o : sample_observations()) entries.emplace_back(o);
  const auto back = read_from_memory(write_to_memory(entries, RawlogLayout::Observations));
  expect_same_entries(entries, back);
}

// Every class registered by register_obs_classes, including types added
// after this test was written, goes through the format: a default object of
// each observation class round-trips as a layout #2 entry, and of each
// action class inside an action collection.
TEST(RoveRawlog, EveryRegisteredClassRoundTrips) {
  register_obs_classes();
  ClassRegistry registry;
  register_obs_classes(registry);
  std::vector<RawlogEntry> observations, frames;
  for (const auto& name : registry.names()) {
    std::unique_ptr<Serializable> obj = registry.create(name);
    if (auto* o = dynamic_cast<Observation*>(obj.get())) {
      observations.emplace_back(std::shared_ptr<const Observation>(o->clone()));
    } else if (auto* a = dynamic_cast<Action*>(obj.get())) {
      auto ac = std::make_shared<ActionCollection>();
      ac->add(std::shared_ptr<const Action>(a->clone()));
      frames.emplace_back(std::shared_ptr<const ActionCollection>(ac));
    }
  }
  EXPECT_GE(observations.size(), 8u);
  EXPECT_GE(frames.size(), 1u);
  expect_same_entries(observations,
                      read_from_memory(write_to_memory(observations, RawlogLayout::Observations)));
  expect_same_entries(frames,
                      read_from_memory(write_to_memory(frames, RawlogLayout::ActionsSensoryFrames)));
}

TEST(RoveRawlog, WriterRejectsEntriesOutsideItsLayout) {
  RoveRawlogWriterOptions o;
  o.layout = RawlogLayout::ActionsSensoryFrames;
  RoveRawlogWriter w(std::make_unique<MemoryOutStream>(), o);
  EXPECT_THROW(w.write(*sample_observations()[0]), InvalidArgument);
  o.layout = RawlogLayout::Observations;
  RoveRawlogWriter w2(std::make_unique<MemoryOutStream>(), o);
  EXPECT_THROW(w2.write(SensoryFrame{}), InvalidArgument);
  o.layout = RawlogLayout::Empty;
  EXPECT_THROW(RoveRawlogWriter(std::make_unique<MemoryOutStream>(), o), InvalidArgument);
}

TEST(RoveRawlog, EmptyLogRoundTrips) {
  const auto bytes = write_to_memory({}, RawlogLayout::Observations);
  EXPECT_EQ(bytes.size(), 8u + 2u + 1u + 4u + 16u);
  EXPECT_TRUE(read_from_memory(bytes).empty());
}

// The frozen file was written by format version 1 with the entries of
// sample_layout1() and must stay readable, entry for entry, forever. Its
// bytes also pin the encoding: writing the same entries today gives the same
// bytes. (ROVE_WRITE_FROZEN=1 rewrites it; only for a new format version.)
TEST(RoveRawlog, FrozenVersion1FileStaysReadable) {
  const auto entries = sample_layout1();
  const RawlogMetadata metadata = {{"source", "rove_rawlog_test"}, {"tool", "rove 0.1.0"}};
  if (std::getenv("ROVE_WRITE_FROZEN") != nullptr) {
    RoveRawlogWriterOptions o;
    o.gzip = false;
    o.metadata = metadata;
    save_rove_rawlog(kFrozen, entries, o);
  }
  ASSERT_TRUE(std::filesystem::exists(kFrozen)) << kFrozen;
  const RoveRawlog back = load_rove_rawlog(kFrozen);
  EXPECT_EQ(back.metadata, metadata);
  EXPECT_EQ(back.layout, RawlogLayout::ActionsSensoryFrames);
  expect_same_entries(entries, back.entries);
  EXPECT_EQ(read_bytes(kFrozen),
            write_to_memory(entries, RawlogLayout::ActionsSensoryFrames, metadata));
}

ParseError parse_error_of(const std::vector<std::byte>& bytes,
                          RoveRawlogReaderOptions options = {}) {
  try {
    read_from_memory(bytes, options);
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError";
  return ParseError({}, "");
}

TEST(RoveRawlog, EveryTruncationIsAParseErrorWithFileAndOffset) {
  const auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 700) {
    const std::vector<std::byte> part(bytes.begin(), bytes.begin() + static_cast<long>(cut));
    const ParseError e = parse_error_of(part);
    EXPECT_EQ(e.location().source, "mem.rawlog") << cut;
    ASSERT_TRUE(e.location().offset.has_value()) << cut;
    EXPECT_LE(*e.location().offset, cut) << cut;
  }
}

TEST(RoveRawlog, CorruptBytesNeverCrash) {
  // Flip every byte in turn: the reader either reads something (a flipped
  // float is still a float) or throws ParseError; nothing else.
  const auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  for (std::size_t i = 0; i < bytes.size(); i += 1 + bytes.size() / 700) {
    auto bad = bytes;
    bad[i] = static_cast<std::byte>(std::to_integer<unsigned>(bad[i]) ^ 0xA5u);
    try {
      read_from_memory(bad);
    } catch (const ParseError&) {
    }
  }
}

// The offsets of the header fields and of the first entry.
constexpr std::size_t kLayoutAt = 10;
constexpr std::size_t kFirstEntryAt = 15;  // no metadata

TEST(RoveRawlog, MalformedHeadersNameTheField) {
  auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  auto bad = bytes;
  bad[0] = std::byte{'X'};
  EXPECT_EQ(parse_error_of(bad).location().field, "magic");
  bad = bytes;
  bad[8] = std::byte{2};
  EXPECT_EQ(parse_error_of(bad).location().field, "format version");
  bad = bytes;
  bad[kLayoutAt] = std::byte{7};
  EXPECT_EQ(parse_error_of(bad).location().field, "layout");
  EXPECT_EQ(*parse_error_of(bad).location().offset, kLayoutAt);
  bad = bytes;
  bad[14] = std::byte{0x7f};  // metadata count above the length limit
  EXPECT_EQ(parse_error_of(bad).location().field, "metadata count");
}

TEST(RoveRawlog, HostileEntryLengthIsRejectedBeforeAllocating) {
  auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  for (int i = 0; i < 8; ++i) bytes[kFirstEntryAt + i] = std::byte{0xff};
  const ParseError e = parse_error_of(bytes);
  EXPECT_EQ(e.location().field, "entry length");
  EXPECT_EQ(*e.location().offset, kFirstEntryAt);
}

TEST(RoveRawlog, EntryLengthDisagreeingWithItsObjectIsAParseError) {
  auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  // One byte more than the record: the object ends early.
  bytes[kFirstEntryAt] = static_cast<std::byte>(std::to_integer<unsigned>(bytes[kFirstEntryAt]) + 1);
  const ParseError e = parse_error_of(bytes);
  EXPECT_EQ(e.location().field, "SensoryFrame");
}

TEST(RoveRawlog, UnknownClassIsNamedOrSkipped) {
  // A record of a class this build does not know, written by hand.
  std::vector<RawlogEntry> entries;
  entries.emplace_back(sample_observations()[2]);
  auto bytes = write_to_memory(entries, RawlogLayout::Observations);
  const std::string name = "FutureSensor";
  std::vector<std::byte> record;
  auto put = [&record](std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) record.push_back(static_cast<std::byte>((v >> (8 * i)) & 0xff));
  };
  put(name.size(), 4);
  for (char c : name) record.push_back(static_cast<std::byte>(c));
  put(1, 1);            // version
  put(0xdeadbeef, 4);   // payload
  put(0x88, 1);         // end marker
  std::vector<std::byte> entry;
  for (int i = 0; i < 8; ++i) entry.push_back(static_cast<std::byte>((record.size() >> (8 * i)) & 0xff));
  entry.insert(entry.end(), record.begin(), record.end());
  // Insert before the end record (16 bytes) and fix the count.
  bytes.insert(bytes.end() - 16, entry.begin(), entry.end());
  bytes[bytes.size() - 8] = std::byte{2};

  const ParseError e = parse_error_of(bytes);
  EXPECT_EQ(e.location().field, "FutureSensor");
  EXPECT_NE(e.problem().find("unknown class"), std::string::npos);

  RoveRawlogReaderOptions skip;
  skip.skip_unknown_classes = true;
  std::uint64_t skipped = 0;
  const auto back = read_from_memory(bytes, skip, &skipped);
  EXPECT_EQ(skipped, 1u);
  expect_same_entries(entries, back);
}

TEST(RoveRawlog, EndRecordIsChecked) {
  const auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  auto bad = bytes;
  bad[bad.size() - 8] = std::byte{9};
  EXPECT_EQ(parse_error_of(bad).location().field, "entry count");
  bad = bytes;
  bad.push_back(std::byte{0});
  EXPECT_EQ(parse_error_of(bad).location().field, "end record");
  // Without the end record (a writer that was not closed): truncated.
  bad.assign(bytes.begin(), bytes.end() - 16);
  EXPECT_EQ(parse_error_of(bad).location().field, "entry length");
}

TEST(RoveRawlog, EntryOutsideTheDeclaredLayoutIsAParseError) {
  auto bytes = write_to_memory(sample_layout1(), RawlogLayout::ActionsSensoryFrames);
  bytes[kLayoutAt] = std::byte{2};  // claims observations only
  const ParseError e = parse_error_of(bytes);
  EXPECT_EQ(e.location().field, "SensoryFrame");
  EXPECT_EQ(*e.location().offset, kFirstEntryAt + 8);
}

TEST(RoveRawlog, WriterWithoutCloseLeavesATruncatedFile) {
  const std::string path = temp_path("unclosed.rawlog");
  {
    RoveRawlogWriter w(path);
    for (const auto& e : sample_layout1()) w.write(e);
  }
  RoveRawlogReader r(path);
  EXPECT_THROW(
      {
        while (r.next()) {
        }
      },
      ParseError);
  std::filesystem::remove(path);
}

TEST(RoveRawlog, MrptRawlogConvertsWithoutLoss) {
  // Every entry of the bundled MRPT rawlog survives rove's format unchanged.
  const std::string mrpt = std::string(ROVE_SOURCE_DIR) +
                           "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
  EXPECT_EQ(detect_rawlog_format(mrpt), RawlogFormat::Mrpt);
  const Rawlog in = load_rawlog(mrpt);
  ASSERT_EQ(in.entries.size(), 449u);
  const std::string path = temp_path("sena.rawlog");
  save_rove_rawlog(path, in.entries);
  const RoveRawlog back = load_rove_rawlog(path);
  EXPECT_EQ(back.layout, RawlogLayout::ActionsSensoryFrames);
  expect_same_entries(in.entries, back.entries);
  std::filesystem::remove(path);
}

TEST(RoveRawlog, FormatDetection) {
  EXPECT_EQ(detect_rawlog_format(kData + "carmen_intel_head.clf"), RawlogFormat::Carmen);
  EXPECT_EQ(detect_rawlog_format(kData + "mrpt_carmen2rawlog_intel_head.rawlog"),
            RawlogFormat::Mrpt);
  EXPECT_EQ(detect_rawlog_format(kFrozen), RawlogFormat::Rove);
  const std::string empty = temp_path("empty");
  { std::ofstream f(empty); }
  try {
    detect_rawlog_format(empty);
    ADD_FAILURE() << "empty file accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, empty);
    EXPECT_EQ(e.location().field, "format");
  }
  std::filesystem::remove(empty);
  EXPECT_THROW(detect_rawlog_format(temp_path("does_not_exist")), IoError);
}

}  // namespace
}  // namespace rove
