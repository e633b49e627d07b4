#pragma once
/// \file
/// Reading and writing pose graphs: TORO/MRPT `.graph`, g2o `.g2o`, and
/// rove's compressed binary form.
///
/// Text records (tags are case-insensitive, as MRPT reads them; blank lines
/// and lines starting with '#' are skipped):
///   VERTEX2 id x y θ                      (also VERTEX, VERTEX_SE2)
///   EDGE2 i j dx dy dθ I_xx I_xy I_yy I_θθ I_xθ I_yθ      (TORO order; also EDGE, ODOMETRY)
///   EDGE_SE2 i j dx dy dθ I_xx I_xy I_xθ I_yy I_yθ I_θθ   (g2o order: upper triangle by rows)
///   VERTEX3 id x y z roll pitch yaw
///   EDGE3 i j dx dy dz roll pitch yaw  + 21 upper-triangular entries, rows of
///         (x, y, z, roll, pitch, yaw)
///   VERTEX_SE3:QUAT id x y z qx qy qz qw
///   EDGE_SE3:QUAT i j dx dy dz qx qy qz qw + 21 upper-triangular entries of Ω
///   EQUIV a b        (topological merge: the larger id becomes the smaller)
///   FIX id [id ...]  (anchored vertices)
/// Angles in radians, R = Rz(yaw)·Ry(pitch)·Rx(roll).
///
/// EDGE3's information is on the Euler angles; rove's 3D error uses the
/// quaternion vector q.xyz ≈ ω/2 (see pose_graph.h), so the rotational rows
/// and columns are scaled by 2 on reading (Ω_q = S·Ω·S, S = diag(1,1,1,2,2,2))
/// and by ½ on writing: the cost of a small error is the same in both forms.
/// EDGE3 / EDGE_SE3:QUAT lines may omit the information block entirely (MRPT
/// then assumes the identity, and so does rove); a partial block is an error.
///
/// A file whose edges refer to vertices but holds no vertex record at all
/// gets its vertices from the odometry chain (initialize_odometry()). Edges
/// that become self loops through EQUIV are dropped (as MRPT does); an
/// explicit self loop is an error.
///
/// Every problem in a file raises rove::ParseError naming the file, the
/// 1-based line (text) or byte offset (binary) and the field: malformed or
/// non-finite numbers, unknown tags, a 3D record in a 2D graph, duplicated
/// vertices, edges to missing vertices, information matrices that are not
/// symmetric positive definite (unless GraphReadOptions::repair_information
/// says how to repair them; the error counts them and names the first),
/// zero quaternions.
///
/// Reading is bounded: only regular files are read (a directory, a device
/// such as /dev/zero or a FIFO is refused with rove::IoError naming it), and
/// at most GraphReadOptions::max_bytes (after gzip decompression).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rove/graph/pose_graph.h"

namespace rove {

class OutArchive;
class InArchive;

/// File formats for pose graphs.
enum class GraphFileFormat {
  Auto,    ///< from the file name on writing (.g2o → G2o, .rpg/.rpg.gz/.bin → Binary,
           ///< anything else → Toro); from the content on reading
  Toro,    ///< TORO/MRPT text (VERTEX2/EDGE2, VERTEX3/EDGE3, EQUIV, FIX)
  G2o,     ///< g2o text (VERTEX_SE2/EDGE_SE2, VERTEX_SE3:QUAT/EDGE_SE3:QUAT, FIX)
  Binary,  ///< rove binary (versioned archive, gzip-compressed)
};

/// What to do with an edge whose information matrix is not positive definite.
enum class InformationRepair {
  None,        ///< refuse the file (ParseError naming the first such edge and the count)
  NearestPsd,  ///< replace it by nearest_positive_definite() (pose_graph.h) and count it
};

/// "none", "nearest-psd".
std::string_view to_string(InformationRepair repair);
/// Inverse of to_string(InformationRepair); std::nullopt for other text.
std::optional<InformationRepair> parse_information_repair(std::string_view text);

/// Options of the graph readers; defaults in the comments.
struct GraphReadOptions {
  /// Edges whose information matrix is not positive definite (g2o and
  /// SE-Sync accept them; SE-Sync's cubicle.g2o has 5,021 of 16,869): refused
  /// by default, or repaired when asked.
  InformationRepair repair_information = InformationRepair::None;
  /// NearestPsd: eigenvalues are clamped to this fraction of the largest |λ|.
  double repair_floor = 1e-6;
  /// Largest file (bytes after gzip decompression) read: 4 GiB. The
  /// machine's memory budget (rove/core/memory_budget.h) applies as well.
  std::uint64_t max_bytes = std::uint64_t{4} << 30;
};

/// What a reader did besides parsing.
struct GraphReadReport {
  std::size_t edges = 0;                       ///< edge records read
  std::size_t repaired_edges = 0;              ///< information matrices repaired
  std::optional<std::size_t> first_repaired_line;  ///< 1-based line of the first one
  bool built_from_odometry = false;  ///< the file had edges but no vertex record: the poses
                                     ///< come from the odometry chain (initialize_odometry())
  std::size_t merged_edges_dropped = 0;  ///< edges that became self loops through EQUIV
};

/// Dimension of the graph a file holds.
enum class GraphDimension { Unknown, TwoD, ThreeD };

/// Looks at the first vertex or edge record of a text file, or the header of
/// a binary one, and says whether it holds a 2D or 3D graph (Unknown for a
/// file without any). Throws IoError if it cannot be read (or is not a
/// regular file, or is larger than `max_bytes`).
GraphDimension detect_graph_dimension(const std::string& path,
                                      std::uint64_t max_bytes = GraphReadOptions{}.max_bytes);

/// Reads a 2D graph from a text (TORO or g2o, plain or gzip) or binary file.
/// `report`, when given, receives what the reader did (repairs, odometry).
PoseGraph2D read_graph_2d(const std::string& path, const GraphReadOptions& options = {},
                          GraphReadReport* report = nullptr);
/// Reads a 3D graph from a text (TORO or g2o, plain or gzip) or binary file.
PoseGraph3D read_graph_3d(const std::string& path, const GraphReadOptions& options = {},
                          GraphReadReport* report = nullptr);

/// Parses a 2D graph from text; `source` names it in errors.
PoseGraph2D parse_graph_2d(std::string_view text, std::string_view source = "<string>",
                           const GraphReadOptions& options = {},
                           GraphReadReport* report = nullptr);
/// Parses a 3D graph from text; `source` names it in errors.
PoseGraph3D parse_graph_3d(std::string_view text, std::string_view source = "<string>",
                           const GraphReadOptions& options = {},
                           GraphReadReport* report = nullptr);

/// The graph as text in `format` (Toro or G2o). Numbers are written with the
/// shortest representation that reads back to the same double. Edge levels
/// and robust kernels have no text form and are not written.
std::string format_graph(const PoseGraph2D& graph, GraphFileFormat format);
/// The graph as text in `format` (Toro or G2o).
std::string format_graph(const PoseGraph3D& graph, GraphFileFormat format);

/// Writes a graph; `format` Auto chooses from the file name (see
/// GraphFileFormat). The file is written under a temporary name beside
/// `path` and renamed when complete (rove/core/files.h), so a failure never
/// leaves a partial file. Throws IoError if the file cannot be written.
void write_graph(const PoseGraph2D& graph, const std::string& path,
                 GraphFileFormat format = GraphFileFormat::Auto);
/// Writes a 3D graph (see the 2D overload).
void write_graph(const PoseGraph3D& graph, const std::string& path,
                 GraphFileFormat format = GraphFileFormat::Auto);

/// Binary record (version 1): magic "rove-pg", dimension, vertices (id,
/// fixed, pose), edges (ends, measurement, upper triangle of Ω, level,
/// kernel). Everything round-trips exactly, levels and kernels included.
void save(OutArchive& ar, const PoseGraph2D& graph);
/// Reads a 2D graph record; ParseError with the byte offset on bad data.
void load(InArchive& ar, PoseGraph2D& graph);
/// Binary record of a 3D graph (see the 2D overload).
void save(OutArchive& ar, const PoseGraph3D& graph);
/// Reads a 3D graph record; ParseError with the byte offset on bad data.
void load(InArchive& ar, PoseGraph3D& graph);

}  // namespace rove
