// Lie groups: rove.SO3, rove.SE2, rove.SE3 (rove/math/so3.h, se2.h, se3.h).
// Plain values, copied between Python and C++ (they are a few numbers).
// Tangent vectors put translation first; perturbations are on the right
// (X ⊕ δ = X·exp(δ)); see docs/conventions.md, "Lie groups".

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/operators.h>

#include "bindings.h"
#include "rove/core/check.h"
#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/math/so3.h"

namespace rove::python {

namespace {

template <typename G>
typename G::Tangent finite_tangent(const typename G::Tangent& xi) {
  ROVE_CHECK_FINITE(xi);
  return xi;
}

// Points (N, dim) moved by the group element: p' = X·p, row by row.
template <typename G>
Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> act_rows(const G& g,
                                                                                py::handle pts) {
  constexpr int kDim = G::Point::RowsAtCompileTime;
  auto m = matrix_arg(pts, "points", kDim, false);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const typename G::Point p = m.row(i).transpose();
    m.row(i) = (g * p).transpose();
  }
  return m;
}

// What every group has: exp/log, hat/vee, inverse, compose, act, Adj,
// oplus/ominus, Jacobians, matrix, is_approx, equality-free (use
// is_approx), pickling through the matrix.
template <typename G>
void bind_group_common(py::class_<G>& c) {
  using Tangent = typename G::Tangent;
  c.def_static("identity", &G::identity, "The identity.")
      .def_static(
          "exp", [](const Tangent& xi) { return G::exp(finite_tangent<G>(xi)); }, py::arg("xi"),
          "exp of a tangent vector (translation first).")
      .def(
          "log", [](const G& g) { return g.log(); }, "The tangent vector (translation first).")
      .def_static(
          "hat", [](const Tangent& xi) { return G::hat(xi); }, py::arg("xi"))
      .def_static(
          "vee", [](const typename G::LieAlgebra& M) { return G::vee(M); }, py::arg("M"))
      .def("inverse", [](const G& g) { return g.inverse(); })
      .def(
          "compose", [](const G& a, const G& b) { return a.compose(b); }, py::arg("other"),
          "self · other")
      .def(
          "__mul__", [](const G& a, const G& b) { return a * b; }, py::is_operator())
      .def(
          "act", [](const G& g, const typename G::Point& p) -> typename G::Point { return g * p; },
          py::arg("point"), "The point moved: X·p.")
      .def("act_points", &act_rows<G>, py::arg("points"),
           "Every row of an (N, dim) array moved: X·p (a new float64 array).")
      .def(
          "adjoint", [](const G& g) { return g.Adj(); }, "The adjoint matrix Adj(X).")
      .def(
          "oplus", [](const G& g, const Tangent& d) { return g.oplus(finite_tangent<G>(d)); },
          py::arg("delta"), "X·exp(delta)")
      .def(
          "ominus", [](const G& g, const G& other) { return g.ominus(other); }, py::arg("other"),
          "log(other⁻¹·X)")
      .def_static(
          "right_jacobian", [](const Tangent& xi) { return G::right_jacobian(xi); }, py::arg("xi"))
      .def_static(
          "left_jacobian", [](const Tangent& xi) { return G::left_jacobian(xi); }, py::arg("xi"))
      .def(
          "matrix", [](const G& g) { return g.matrix(); }, "The homogeneous (or rotation) matrix.")
      .def(
          "is_approx", [](const G& a, const G& b, double tol) { return a.is_approx(b, tol); },
          py::arg("other"), py::arg("tol") = 1e-10)
      .def(py::pickle([](const G& g) { return py::make_tuple(g.matrix()); },
                      [](const py::tuple& t) { return G(t[0].cast<typename G::LieAlgebra>()); }))
      .def_property_readonly_static("dof", [](py::object) { return G::kDof; });
}

double finite_angle(double a) {
  ROVE_CHECK_FINITE(a);
  return a;
}

}  // namespace

void bind_geometry(py::module_& m) {
  py::class_<SO3d> so3(m, "SO3", "A 3D rotation (unit quaternion inside). Tangent: ω (rad).");
  so3.def(py::init<>())
      .def(py::init([](const Eigen::Matrix3d& R) { return SO3d(R); }), py::arg("R"),
           "From a rotation matrix (orthonormal within 1e-9, det > 0; else ValueError).")
      .def_static(
          "from_quaternion",
          [](double w, double x, double y, double z) {
            return SO3d::from_unnormalized(Eigen::Quaterniond(w, x, y, z));
          },
          py::arg("w"), py::arg("x"), py::arg("y"), py::arg("z"),
          "From a non-zero quaternion (normalized).")
      .def_static(
          "rot_x", [](double a) { return SO3d::rot_x(finite_angle(a)); }, py::arg("angle"),
          "Rotation about x by angle (rad).")
      .def_static(
          "rot_y", [](double a) { return SO3d::rot_y(finite_angle(a)); }, py::arg("angle"),
          "Rotation about y by angle (rad).")
      .def_static(
          "rot_z", [](double a) { return SO3d::rot_z(finite_angle(a)); }, py::arg("angle"),
          "Rotation about z by angle (rad).")
      .def_property_readonly(
          "quaternion",
          [](const SO3d& r) {
            const auto& q = r.quaternion();
            return Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
          },
          "(w, x, y, z)")
      .def("__repr__", [](const SO3d& r) {
        const auto& q = r.quaternion();
        return fmt::format("rove.SO3(w={:.6g}, x={:.6g}, y={:.6g}, z={:.6g})", q.w(), q.x(), q.y(),
                           q.z());
      });
  bind_group_common(so3);

  py::class_<SE2d> se2(m, "SE2", "A 2D rigid transform. Tangent: (rho_x, rho_y, theta).");
  se2.def(py::init<>())
      .def(py::init<double, double, double>(), py::arg("x"), py::arg("y"), py::arg("theta"),
           "From x, y (m) and heading theta (rad).")
      .def_static(
          "from_matrix", [](const Eigen::Matrix3d& M) { return SE2d(M); }, py::arg("M"))
      .def_property_readonly("x", [](const SE2d& g) { return g.translation().x(); })
      .def_property_readonly("y", [](const SE2d& g) { return g.translation().y(); })
      .def_property_readonly(
          "theta", [](const SE2d& g) { return g.angle(); }, "Heading, rad.")
      .def_property_readonly("translation", [](const SE2d& g) { return g.translation(); })
      .def_property_readonly("rotation_matrix", [](const SE2d& g) { return g.rotation_matrix(); })
      .def("__repr__", [](const SE2d& g) {
        return fmt::format("rove.SE2(x={:.6g}, y={:.6g}, theta={:.6g})", g.translation().x(),
                           g.translation().y(), g.angle());
      });
  bind_group_common(se2);

  py::class_<SE3d> se3(m, "SE3", "A 3D rigid transform. Tangent: (rho, omega).");
  se3.def(py::init<>())
      .def(py::init([](const Eigen::Matrix3d& R, const Eigen::Vector3d& t) { return SE3d(R, t); }),
           py::arg("R"), py::arg("t"), "From a rotation matrix and a translation (m).")
      .def(py::init([](const SO3d& R, const Eigen::Vector3d& t) { return SE3d(R, t); }),
           py::arg("rotation"), py::arg("t"))
      .def_static(
          "from_matrix", [](const Eigen::Matrix4d& M) { return SE3d(M); }, py::arg("M"))
      .def_property_readonly("translation", [](const SE3d& g) { return g.translation(); })
      .def_property_readonly("rotation", [](const SE3d& g) { return g.rotation(); })
      .def_property_readonly("rotation_matrix", [](const SE3d& g) { return g.rotation_matrix(); })
      .def("__repr__", [](const SE3d& g) {
        const auto& t = g.translation();
        const auto& q = g.quaternion();
        return fmt::format(
            "rove.SE3(t=({:.6g}, {:.6g}, {:.6g}), q=({:.6g}, {:.6g}, {:.6g}, {:.6g}))", t.x(),
            t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
      });
  bind_group_common(se3);
}

}  // namespace rove::python
