"""rove.SE2 / SE3 / SO3 against closed forms and numpy matrix algebra."""

import math
import pickle

import numpy as np
import pytest

import rove


def test_se2_exp_closed_form():
    # exp([1, 0, pi/2]): translation V(theta)·rho = (sin θ/θ, (1 − cos θ)/θ) = (2/π, 2/π).
    g = rove.SE2.exp(np.array([1.0, 0.0, math.pi / 2]))
    assert g.x == pytest.approx(2 / math.pi, abs=1e-15)
    assert g.y == pytest.approx(2 / math.pi, abs=1e-15)
    assert g.theta == pytest.approx(math.pi / 2, abs=1e-15)
    np.testing.assert_allclose(g.log(), [1.0, 0.0, math.pi / 2], atol=1e-14)


def test_se2_compose_inverse_act_match_matrices():
    a, b = rove.SE2(1.0, -2.0, 0.3), rove.SE2(-0.5, 4.0, -2.0)
    np.testing.assert_allclose((a * b).matrix(), a.matrix() @ b.matrix(), atol=1e-14)
    np.testing.assert_allclose(a.inverse().matrix(), np.linalg.inv(a.matrix()), atol=1e-14)
    pts = np.array([[1.0, 2.0], [-3.0, 0.5], [0.0, 0.0]])
    moved = a.act_points(pts)
    homo = (a.matrix() @ np.c_[pts, np.ones(3)].T).T[:, :2]
    np.testing.assert_allclose(moved, homo, atol=1e-14)
    np.testing.assert_allclose(a.act([1.0, 2.0]), homo[0], atol=1e-14)
    # ominus/oplus are inverse to each other.
    d = b.ominus(a)
    assert a.oplus(d).is_approx(b, 1e-12)


def test_se3_exp_log_and_rotation():
    xi = np.array([0.4, -1.0, 2.0, 0.3, -0.2, 0.9])
    g = rove.SE3.exp(xi)
    np.testing.assert_allclose(g.log(), xi, atol=1e-13)
    R = g.rotation_matrix
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    # The rotation part is exp of the hat of omega: Rodrigues' formula.
    w = xi[3:]
    th = np.linalg.norm(w)
    K = rove.SO3.hat(w) / th
    rodrigues = np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K
    np.testing.assert_allclose(R, rodrigues, atol=1e-14)
    h = rove.SE3(rove.SO3.rot_z(0.5), [1.0, 2.0, 3.0])
    np.testing.assert_allclose((g * h).matrix(), g.matrix() @ h.matrix(), atol=1e-13)
    np.testing.assert_allclose(g.adjoint() @ xi, xi, atol=1e-13)  # Adj(exp(xi)) xi = xi


def test_so3_quaternion_and_axes():
    r = rove.SO3.rot_z(math.pi / 2)
    np.testing.assert_allclose(r.quaternion, [math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)],
                               atol=1e-15)
    np.testing.assert_allclose(r.act([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-15)
    q = rove.SO3.from_quaternion(2.0, 0.0, 0.0, 0.0)  # normalized
    np.testing.assert_allclose(q.matrix(), np.eye(3))


def test_jacobians_against_numeric():
    xi = np.array([0.2, -0.1, 0.7])
    J = rove.SE2.right_jacobian(xi)
    eps = 1e-6
    numeric = np.zeros((3, 3))
    base = rove.SE2.exp(xi)
    for k in range(3):
        d = np.zeros(3)
        d[k] = eps
        numeric[:, k] = rove.SE2.exp(xi + d).ominus(base) / eps
    np.testing.assert_allclose(J, numeric, atol=1e-5)


def test_pickle_round_trip():
    for g in (rove.SE2(1.0, 2.0, 0.5), rove.SE3.exp(np.arange(6) * 0.1), rove.SO3.rot_x(0.2)):
        h = pickle.loads(pickle.dumps(g))
        assert type(h) is type(g)
        assert h.is_approx(g, 1e-12)


def test_bad_values_are_value_errors():
    with pytest.raises(ValueError, match="finite"):
        rove.SE2(float("nan"), 0.0, 0.0)
    with pytest.raises(rove.InvalidArgument, match="orthonormal"):
        rove.SE3(np.eye(3) * 2.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError):
        rove.SE3.exp(np.array([0, 0, 0, float("inf"), 0, 0]))
    with pytest.raises(ValueError):
        rove.SO3.from_quaternion(0.0, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError):
        rove.SE2.exp(np.array([1.0, float("nan"), 0.0]))
    with pytest.raises(TypeError):
        rove.SE2.exp(np.array([1.0, 2.0]))  # wrong size: no conversion applies
    with pytest.raises(ValueError, match="shape"):
        rove.SE2().act_points(np.zeros((4, 3)))
    e = pytest.raises(ValueError, rove.SE2, 0.0, float("inf"), 0.0).value
    assert isinstance(e, rove.Error) and e.trace  # rove's frames are kept
