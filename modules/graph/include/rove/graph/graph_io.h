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
/// symmetric positive definite, zero quaternions.

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

/// Dimension of the graph a file holds.
enum class GraphDimension { Unknown, TwoD, ThreeD };

/// Looks at the first vertex or edge record of a text file, or the header of
/// a binary one, and says whether it holds a 2D or 3D graph (Unknown for a
/// file without any). Throws IoError if it cannot be read.
GraphDimension detect_graph_dimension(const std::string& path);

/// Reads a 2D graph from a text (TORO or g2o, plain or gzip) or binary file.
PoseGraph2D read_graph_2d(const std::string& path);
/// Reads a 3D graph from a text (TORO or g2o, plain or gzip) or binary file.
PoseGraph3D read_graph_3d(const std::string& path);

/// Parses a 2D graph from text; `source` names it in errors.
PoseGraph2D parse_graph_2d(std::string_view text, std::string_view source = "<string>");
/// Parses a 3D graph from text; `source` names it in errors.
PoseGraph3D parse_graph_3d(std::string_view text, std::string_view source = "<string>");

/// The graph as text in `format` (Toro or G2o). Numbers are written with the
/// shortest representation that reads back to the same double. Edge levels
/// and robust kernels have no text form and are not written.
std::string format_graph(const PoseGraph2D& graph, GraphFileFormat format);
/// The graph as text in `format` (Toro or G2o).
std::string format_graph(const PoseGraph3D& graph, GraphFileFormat format);

/// Writes a graph; `format` Auto chooses from the file name (see
/// GraphFileFormat). Throws IoError if the file cannot be written.
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
