#pragma once
/// \file
/// Whole-file rawlog jobs behind `rove rawlog convert|cut|decimate|
/// export-scans|export-odometry`: each streams its input once (any format
/// AnyRawlogReader reads) in constant memory and writes a rove rawlog or
/// text files, and returns what it kept and dropped.
///
/// Every job refuses an output that resolves to its input (IoError, before
/// anything is opened), writes each output under a temporary name beside it
/// and renames it only when complete (an error or Ctrl-C leaves no partial
/// file, and an older file of that name intact), polls
/// rove::throw_if_interrupted() once per entry, and throws SelectionError
/// (selection_error.h) when it would write nothing: a cut outside the log,
/// an export of a label that is not there or of a log without such data.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rove/io/any_rawlog.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/selection_error.h"

namespace rove {

/// Called after each input entry with the reader (for position()); may be
/// empty.
using RawlogProgressFn = std::function<void(const AnyRawlogReader&)>;

/// What a job read, wrote and left out.
struct RawlogJobResult {
  /// The input's format.
  RawlogFormat input_format = RawlogFormat::Mrpt;
  /// Entries read from the input.
  std::uint64_t entries_in = 0;
  /// Entries written to the output rawlog (0 for text exports).
  std::uint64_t entries_out = 0;
  /// Observations and actions written (or exported), by class name.
  std::map<std::string, std::uint64_t> kept;
  /// Observations, actions and entries left out, by class name (or a
  /// description such as "CARMEN ODOM line").
  std::map<std::string, std::uint64_t> dropped;
  /// Text exports: the files written, in the order they were created.
  std::vector<std::string> files;
  /// Text exports: rows written per file (same order as files).
  std::vector<std::uint64_t> rows;
  /// What the reader left out (AnyRawlogReader::skipped; convert_rawlog).
  std::vector<std::string> reader_skipped;
};

/// Options of convert_rawlog.
struct ConvertOptions {
  /// Output layout: std::nullopt keeps the input's (CARMEN: layout #1);
  /// kActionsSensoryFrames or kObservations converts (see convert_rawlog).
  std::optional<RawlogLayout> layout;
  /// Reading options (CARMEN's motion model and labels, limits). Its
  /// carmen.layout is overridden by `layout` when that is set.
  AnyRawlogOptions read;
  /// Writing options (gzip, level); metadata "source" and "tool" are added.
  RoveRawlogWriterOptions write;
  /// Motion model of the actions made when converting #2 → #1.
  MotionModelOptions motion_model;
};

/// Converts `in` (rove, MRPT or CARMEN) to a rove rawlog at `out`.
///
/// Without a layout change every entry is kept (an MRPT file that mixes
/// both kinds of entries gives a mixed rove rawlog). Layout changes:
///  - #1 → #2: each sensory frame's observations become bare observations
///    in order; each RobotMovement2D action becomes an OdometryObservation
///    (label "ODOMETRY") holding the odometry integrated from the identity
///    (composing the actions' mean increments), with the action's time,
///    encoder ticks and velocity; other actions are dropped.
///  - #2 → #1: OdometryObservations split the stream: the observations after
///    an odometry reading go into one sensory frame, preceded by an action
///    collection with a RobotMovement2D of the increment since the reading
///    that preceded the previous frame (options.motion_model); observations
///    before any odometry form the first frame. Odometry readings are
///    consumed (counted in dropped as "OdometryObservation (→ actions)").
/// Throws what the reader throws, IoError on write failure, InvalidArgument
/// if options.layout is kEmpty or kMixed.
RawlogJobResult convert_rawlog(const std::string& in, const std::string& out,
                               const ConvertOptions& options = {},
                               const RawlogProgressFn& progress = {});

/// Which entries cut_rawlog keeps. Indices count input entries from 0;
/// times are seconds since the Unix epoch (an entry's time is that of its
/// earliest timestamped observation, or its action's). Both bounds are
/// inclusive; unset bounds are open.
struct CutOptions {
  std::optional<std::uint64_t> from_index;
  std::optional<std::uint64_t> to_index;
  std::optional<double> from_time;
  std::optional<double> to_time;
  /// Reading options.
  AnyRawlogOptions read;
  /// Writing options.
  RoveRawlogWriterOptions write;
};

/// Writes the entries of `in` within the bounds to a rove rawlog `out`
/// (same layout as the input). Entries without any timestamp pass a time
/// bound when the entry before them did (so an action collection stays with
/// its frame). Reading stops after to_index. Throws InvalidArgument if a
/// lower bound exceeds its upper bound or a time is not finite;
/// SelectionError naming the bounds and the log's index and time range when
/// no entry is within them (nothing is written).
RawlogJobResult cut_rawlog(const std::string& in, const std::string& out,
                           const CutOptions& options, const RawlogProgressFn& progress = {});

/// Options of decimate_rawlog.
struct DecimateOptions {
  /// Keep one of every `every` sensory frames (layout #1) or observations
  /// (layout #2), starting with the first. Must be >= 1.
  std::uint64_t every = 1;
  /// Reading options.
  AnyRawlogOptions read;
  /// Writing options.
  RoveRawlogWriterOptions write;
};

/// Keeps one of every K sensory frames (layout #1: the odometry actions
/// between kept frames are composed into one RobotMovement2D, so odometry
/// stays consistent, as rawlog-edit's --decimate does; the accumulated
/// Gaussian is the composition of the actions' Gaussians) or observations
/// (layout #2: OdometryObservations are absolute, so dropping some keeps
/// the rest consistent). Writes a rove rawlog with the input's layout.
RawlogJobResult decimate_rawlog(const std::string& in, const std::string& out,
                                const DecimateOptions& options,
                                const RawlogProgressFn& progress = {});

/// Options of the text exports.
struct TextExportOptions {
  /// Export only this sensor label (empty: every label).
  std::string label;
  /// Reading options.
  AnyRawlogOptions read;
};

/// Writes 2D range scans as MRPT 2.5.8's `rawlog-edit --export-2d-scans-txt`
/// writes them: a header line "%             Time RANGES[i] ... VALID[i]"
/// (plus " ... INTENSITY[i]" when the scan has intensities), then per scan
/// the time ("%16.6f") and MRPT's data row (ranges "%.03f ", four spaces,
/// validity "%u ", four spaces, intensities "%d "). One file per sensor
/// label: `out` itself when there is one label, else `<out without .txt>_
/// <label>.txt` (MRPT's naming; characters invalid in file names become
/// '_'). Unlike rawlog-edit, the sensory frame before the first action is
/// exported too, and unlabeled scans are exported (as label "").
/// Throws SelectionError (listing the labels present) when no scan matches
/// options.label, or when the log has no 2D scan.
RawlogJobResult export_scans_txt(const std::string& in, const std::string& out,
                                 const TextExportOptions& options = {},
                                 const RawlogProgressFn& progress = {});

/// Writes odometry as `rawlog-edit --export-odometry-txt` writes
/// CObservationOdometry: the time, then x y phi, encoders, velocities
/// (MRPT's exportTxtDataRow columns and widths). Layout #2: one row per
/// OdometryObservation. Layout #1 (where MRPT 2.5.8 writes no odometry
/// file: it ignores actions): the RobotMovement2D actions are integrated
/// from the identity — one row per action with the composed pose, the
/// action's time (or that of the next frame's first observation when the
/// action has none), its encoder ticks and velocity — under label
/// "ODOMETRY"; an identity row first at the time of a frame that precedes
/// the first action. File naming as export_scans_txt.
/// Throws ParseError if a row would have no timestamp; SelectionError
/// (listing the labels present) when nothing matches options.label or the
/// log holds no odometry.
RawlogJobResult export_odometry_txt(const std::string& in, const std::string& out,
                                    const TextExportOptions& options = {},
                                    const RawlogProgressFn& progress = {});

/// MRPT's time column: "%16.6f" of the time in seconds since the Unix epoch
/// computed as mrpt::Clock::toDouble does (from 100-ns ticks).
std::string mrpt_txt_time(Timestamp t);
/// MRPT's CObservation2DRangeScan::exportTxtDataRow.
std::string mrpt_txt_scan_row(const RangeScan2D& scan);
/// MRPT's CObservationOdometry::exportTxtDataRow for these values.
std::string mrpt_txt_odometry_row(const Pose2& odometry, const std::optional<EncoderTicks>& ticks,
                                  const std::optional<Twist2>& velocity);

}  // namespace rove
