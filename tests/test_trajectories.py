"""The motion every integrating exercise hands over (``mech.solve(...).trajectory``, issue 17).

For each exercise with declared states: the times increase, y is n_states x n_times, the first state
is the initial condition the parameters give (worked out by hand below), and one physical check
derived independently of the solver: an invariant evaluated from the states by a formula written
here, or the motion's end matching an output.  A wrong scale, a wrong row or a wrong time unit
fails them by orders of magnitude.
"""

from __future__ import annotations

import math
import pathlib
import re

import numpy as np
import pytest
from click.testing import CliRunner

import mech
from mech.cli.main import cli
from mech.problems import registry


def motion(ex_id, **params):
    sol = mech.solve(ex_id, **params)
    assert sol.agree, sol.errors
    tr = sol.trajectory
    assert tr is not None
    ex = registry.get(ex_id)
    assert tr.names == [s[0] for s in ex.states] and tr.units == [s[1] for s in ex.states]
    assert tr.y.shape == (len(tr.names), tr.t.size) and tr.t.size >= 20
    assert np.all(np.diff(tr.t) > 0) and np.all(np.isfinite(tr.y))
    return sol, tr.t, tr.y


def out(sol, name):
    return sol[name].value


def test_4_7_bullet_and_rod_share_the_momentum_during_the_impact():
    m, l, mb, v0 = 1.0, 0.5, 0.01, 300.0
    sol, t, y = motion("4.7", m=m, l=l, m_b=mb, v0=v0)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [0, 0, 0, 0, 0, 0, 0, 0, v0, 0, 0], rtol=0, atol=1e-12)
    # no external force: m V_rod + m_b v_bullet = m_b v0 along x, 0 across
    assert np.allclose(m * y[5] + mb * y[8], mb * v0, rtol=1e-9)
    assert np.allclose(m * y[6] + mb * y[9], 0.0, atol=1e-9 * mb * v0)
    # after the pulse the bullet moves with the struck end; the energy lost is the dissipated work
    assert y[8, -1] == pytest.approx(out(sol, "v_hit"), rel=1e-6)
    assert y[10, -1] == pytest.approx(out(sol, "E_loss"), rel=1e-6)


def test_4_8_slip_decays_at_seven_halves_mu_g_and_angular_momentum_about_the_contact_is_kept():
    M, R, P, h, b, mu, g = 0.17, 0.028575, 0.34, 0.8, 0.25, 0.2, 9.81
    sol, t, y = motion("4.8", M=M, R=R, P=P, h_over_R=h, b_over_R=b, mu=mu, g=g)
    V0 = P / M
    # the strike: V = V0 x, I w = r x P x with r = (., b R, (h - 1) R), I = 2 M R^2/5
    w_y, w_z = 2.5 * P * (h - 1.0) / (M * R), -2.5 * P * b / (M * R)
    u0 = V0 * (7.0 - 5.0 * h) / 2.0
    assert np.allclose(y[:, 0], [u0, 0, 0, 0, w_y, w_z, 0, 0, 0], rtol=1e-9, atol=1e-9)
    # friction -mu M g along the slip: du/dt = -(1 + M R^2/I) mu g = -(7/2) mu g (times from the strike's centre)
    assert np.allclose(y[0], u0 - 3.5 * mu * g * t, rtol=0, atol=1e-7 * u0)
    # angular momentum about the contact point: I w_y + M R V_x with V_x = slip_x + R w_y
    Lc = 0.4 * M * R**2 * y[4] + M * R * (y[0] + R * y[4])
    assert np.allclose(Lc, Lc[0], rtol=1e-7)
    assert t[-1] == pytest.approx(out(sol, "t_roll"), rel=1e-9) and abs(y[0, -1]) < 1e-9 * u0


def test_4_9_the_cylinder_keeps_its_energy_on_the_quarter_swing():
    M, R, l, I, phi0, g = 1.0, 0.1, 0.03, 0.004, math.pi / 6, 9.81
    sol, t, y = motion("4.9", M=M, R=R, l=l, I=I, phi0=phi0, g=g)
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(phi0, rel=1e-15) and y[1, 0] == 0.0
    phi, w = y
    # rolling without slipping: the centre of mass is (R^2 - 2 R l cos phi + l^2)^(1/2) from the contact
    E = 0.5 * (I + M * (R * R - 2 * R * l * np.cos(phi) + l * l)) * w * w + M * g * l * (1 - np.cos(phi))
    assert np.allclose(E, M * g * l * (1 - math.cos(phi0)), rtol=1e-8)
    assert abs(phi[-1]) < 1e-10 and t[-1] == pytest.approx(out(sol, "period") / 4, rel=1e-9)


def test_4_10_the_small_swing_keeps_its_energy():
    M, I, l, g = 1.0, 0.02, 0.2, 9.81
    sol, t, y = motion("4.10", M=M, I=I, l=l, g=g)
    A = 1e-4  # the cross-check's fixed amplitude, released at rest
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(A, rel=1e-15) and y[1, 0] == 0.0
    E = 0.5 * (I + M * l * l) * y[1] ** 2 + M * g * l * (1 - np.cos(y[0]))
    # E ~ 1e-8 J here: an absolute tolerance would hide any error, so none (integrated at rtol <= 1e-6)
    assert np.allclose(E, M * g * l * (1 - math.cos(A)), rtol=1e-5, atol=0.0)
    # the swing runs 1.5 times the period the integration guesses from the small-oscillation theory:
    # Omega^2 = M g l / (I + M l^2), by hand
    assert t[-1] == pytest.approx(1.5 * 2 * math.pi / math.sqrt(M * g * l / (I + M * l * l)), rel=1e-6)


def test_4_15_the_ladder_starts_at_rest_at_theta0():
    sol, t, y = motion("4.15", theta0=math.pi / 3)
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(math.pi / 3, rel=1e-15) and y[1, 0] == 0.0


def test_4_18_the_ball_rolls_on_the_turntable_without_slipping_on_a_circle():
    Om, R, x0, y0, vx0, vy0 = 3.4906585, 0.02, 0.1, 0.0, 0.05, 0.2
    sol, t, y = motion("4.18", Omega=Om, R=R, x0=x0, y0=y0, vx0=vx0, vy0=vy0)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [x0, y0, vx0, vy0, 0, 0, 0], rtol=0, atol=1e-15)
    x, yy, vx, vy, dwx, dwy, dwz = y
    # no slip: v - R (w x z) = Omega z x r, with its start subtracted
    assert np.allclose((vx - vx0) - R * dwy, -Om * (yy - y0), rtol=0, atol=1e-8)
    assert np.allclose((vy - vy0) + R * dwx, Om * (x - x0), rtol=0, atol=1e-8)
    # the centre runs round the circle the outputs give, at constant speed
    rho = np.hypot(x - out(sol, "xc"), yy - out(sol, "yc"))
    assert np.allclose(rho, out(sol, "r_orbit"), rtol=1e-7)
    assert np.allclose(np.hypot(vx, vy), math.hypot(vx0, vy0), rtol=1e-8)


def _rotate(q, v):
    """Lab components of body vectors v (3 x N) for unit quaternions q (4 x N, scalar first)."""
    w, a, b, c = q / np.linalg.norm(q, axis=0)
    Rm = np.array([[1 - 2 * (b * b + c * c), 2 * (a * b - w * c), 2 * (a * c + w * b)],
                   [2 * (a * b + w * c), 1 - 2 * (a * a + c * c), 2 * (b * c - w * a)],
                   [2 * (a * c - w * b), 2 * (b * c + w * a), 1 - 2 * (a * a + b * b)]])
    return np.einsum("ijn,jn->in", Rm, v)


def test_4_19_the_free_disk_keeps_its_energy_and_its_angular_momentum_along_lab_z():
    omega, alpha = 10.0, 0.05
    sol, t, y = motion("4.19", omega=omega, alpha=alpha)
    assert t[0] == 0.0 and np.allclose(y[:3, 0], omega * np.array([math.sin(alpha), 0, math.cos(alpha)]), atol=1e-14)
    # thin disk: I3 = 2 I1; energy and the lab angular momentum (chosen along z) stay
    L_body = np.array([y[0], y[1], 2 * y[2]])
    E = y[0] ** 2 + y[1] ** 2 + 2 * y[2] ** 2
    assert np.allclose(E, E[0], rtol=1e-8)
    L = _rotate(y[3:7], L_body)
    Lmag = np.linalg.norm(L_body[:, 0])
    assert np.allclose(L[2], Lmag, rtol=1e-8) and np.max(np.abs(L[:2])) < 1e-8 * Lmag
    assert t[-1] == pytest.approx(4 * math.pi / omega, rel=1e-12)  # two spin periods


def test_4_20_the_flip_keeps_energy_and_angular_momentum_over_one_and_a_half_periods():
    I = np.array([2.8e-3, 5.3e-3, 7.9e-3])
    w0, d = 10.0, 0.01
    sol, t, y = motion("4.20", I1=I[0], I2=I[1], I3=I[2], omega0=w0, delta=d)
    assert t[0] == 0.0 and np.allclose(y[:, 0], w0 * np.array([math.sin(d), math.cos(d), 0.0]), rtol=1e-15)
    E, L2 = I @ y**2, (I**2) @ y**2
    assert np.allclose(E, E[0], rtol=1e-8) and np.allclose(L2, L2[0], rtol=1e-8)
    assert y[1, 0] > 0 and np.min(y[1]) < -0.99 * w0  # it flips
    assert t[-1] == pytest.approx(1.5 * out(sol, "T_period"), rel=1e-7)


def test_4_21_the_steady_precession_keeps_its_tilt_and_axial_momentum():
    M, l, I1, I3, w3, th0, g = 0.1, 0.03, 1.5625e-5, 3.125e-5, 400.0, math.pi / 6, 9.81
    sol, t, y = motion("4.21", M=M, l=l, I1=I1, I3=I3, omega3=w3, theta0=th0, g=g)
    n, L = y[:3], y[3:]
    assert t[0] == 0.0 and np.allclose(n[:, 0], [math.sin(th0), 0, math.cos(th0)], atol=1e-15)
    assert np.allclose(np.sum(n * L, axis=0), I3 * w3, rtol=1e-8)  # L . n = L3 = I3 omega3
    assert np.allclose(L[2], L[2, 0], rtol=1e-8)  # gravity's torque is horizontal
    assert np.allclose(n[2], math.cos(th0), atol=1e-7)  # steady: the tilt stays
    # the azimuth turns at the precession rate
    az = np.unwrap(np.arctan2(n[1], n[0]))
    assert az[-1] / t[-1] == pytest.approx(out(sol, "omega_pre"), rel=1e-6)


def test_4_23_the_rolling_coin_keeps_its_energy_height_and_circle():
    r, th, R, g = 0.012, 0.3, 0.1, 9.81
    sol, t, y = motion("4.23", r=r, theta=th, R=R, g=g)
    c0 = [R - r * math.sin(th), 0.0, r * math.cos(th)]  # contact at (R, 0, 0), leaning inward by theta
    assert t[0] == 0.0 and np.allclose(y[7:10, 0], c0, rtol=1e-12, atol=1e-15)
    assert np.allclose(np.linalg.norm(y[3:7], axis=0), 1.0, atol=1e-9)
    # per unit mass; thin disk: I1 = I2 = r^2/4, I3 = r^2/2 about the body axes
    E = 0.5 * np.sum(y[10:13] ** 2, axis=0) + 0.125 * r * r * (y[0] ** 2 + y[1] ** 2 + 2 * y[2] ** 2) + g * y[9]
    assert np.allclose(E, E[0], rtol=1e-8)
    assert np.allclose(y[9], c0[2], rtol=1e-6)
    assert np.allclose(np.hypot(y[7], y[8]), c0[0], rtol=1e-6)


def test_4_24_the_averaged_axis_falls_over_ninety_degrees_ahead_of_the_force():
    """A spin of 1e19 nutation periods per overturn: the route follows the guiding center.  By hand (the
    gyroscopic top in the frame turning with F): the axis turns about -x' at b = l F/L3 from z, so
    c = (0, sin bt, cos bt), within eps = I_A l F/L3^2 ~ 1e-19; the start is z + (b/k) x' normalized,
    k = L3/I_A; |c| = 1.  Tolerance: the claim 10 rtol = 1e-5 of the route's default rtol 1e-6."""
    M, l, I1, I3, w, F, g = 0.0495024, 5.48317e-05, 1.46346e-05, 2.34304, 27467.0, 0.179372, 4.26266
    sol, t, y = motion("4.24", M=M, l=l, I1=I1, I3=I3, omega_rot=w, F=F, g=g)
    L3, IA = I3 * w, I1 + M * l * l
    b, d = l * F / L3, l * F * IA / L3**2
    assert t[0] == 0.0 and np.allclose(y[:, 0], np.array([d, 0.0, 1.0]) / math.hypot(d, 1.0), rtol=1e-15)
    assert np.allclose(np.linalg.norm(y, axis=0), 1.0, atol=1e-5)
    assert np.allclose(y[0], 0.0, atol=1e-5)
    assert np.allclose(y[1], np.sin(b * t), atol=1e-5) and np.allclose(y[2], np.cos(b * t), atol=1e-5)
    assert t[-1] == pytest.approx(12.0 / b, rel=1e-12) and t[-1] > out(sol, "t_up")


def test_4_25_friction_brakes_the_spin_at_mu_M_g_R():
    M, I3, l, R, mu, w0, th0, th1, g = 0.1, 3.125e-5, 0.03, 1e-3, 0.05, 300.0, 0.5, 0.1, 9.81
    sol, t, y = motion("4.25", M=M, I3=I3, l=l, R=R, mu=mu, omega0=w0, theta0=th0, theta1=th1, g=g)
    L0 = I3 * w0
    assert t[0] == 0.0 and np.allclose(y[:, 0], [L0 * math.sin(th0), L0 * math.cos(th0)], rtol=1e-15)
    # the rim's kinetic friction mu M g at radius R: axial torque mu M g R
    assert np.allclose(np.hypot(y[0], y[1]), L0 - mu * M * g * R * t, rtol=1e-8)
    assert math.atan2(y[0, -1], y[1, -1]) == pytest.approx(th1, rel=1e-8)
    assert t[-1] == pytest.approx(out(sol, "t_rise"), rel=1e-9)


def test_4_29_the_bead_runs_out_as_a_cosh():
    sol, t, y = motion("4.29", m=0.1, omega=2.0, r0=0.1, v0=0.0, t=1.0)
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(0.1, rel=1e-15) and y[1, 0] == 0.0
    # r'' = omega^2 r from rest: r = r0 cosh(omega t)
    assert np.allclose(y[0], 0.1 * np.cosh(2.0 * t), rtol=1e-8)
    assert np.allclose(y[1], 0.2 * np.sinh(2.0 * t), rtol=1e-8, atol=1e-12)
    assert t[-1] == 1.0 and y[0, -1] == pytest.approx(out(sol, "r"), rel=1e-9)


def test_4_29_a_bead_at_rest_on_the_axis_has_no_motion():
    assert mech.solve("4.29", r0=0.0, v0=0.0).trajectory is None


def test_4_30_foucault_keeps_energy_and_the_inertial_angular_momentum():
    th, l, g, a, wE = 0.7182029871956666, 67.0, 9.81, 3.0, 7.2921159e-5
    sol, t, y = motion("4.30", theta=th, l=l, g=g, a=a, omega_E=wE)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [a, 0, 0, 0], atol=1e-15)
    x, yy, vx, vy = y
    w0sq, wz = g / l, wE * math.cos(th)  # the vertical part of the Earth's rotation, at colatitude theta
    E = 0.5 * (vx**2 + vy**2) + 0.5 * w0sq * (x**2 + yy**2)  # the Coriolis force does no work
    assert np.allclose(E, 0.5 * w0sq * a * a, rtol=1e-7)
    Lz = x * vy - yy * vx + wz * (x**2 + yy**2)  # angular momentum about the vertical, inertial frame
    assert np.max(np.abs(Lz - wz * a * a)) < 1e-7 * math.sqrt(w0sq) * a * a


def test_4_31_the_falling_body_lands_where_the_outputs_say():
    h, th, g, wE = 381.0, 0.8595746566072073, 9.81, 7.2921159e-5
    sol, t, y = motion("4.31", h=h, theta=th, g=g, omega_E=wE)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [0, 0, h, 0, 0, 0], atol=1e-15)
    E = 0.5 * np.sum(y[3:] ** 2, axis=0) + g * y[2]
    assert np.allclose(E, g * h, rtol=1e-9)
    assert abs(y[2, -1]) < 1e-9 * h and t[-1] == pytest.approx(out(sol, "t_fall"), rel=1e-10)
    assert y[0, -1] == pytest.approx(out(sol, "d_east"), rel=1e-9)
    assert y[3, -1] == pytest.approx(out(sol, "v_east"), rel=1e-9)


def test_4_33_the_relative_path_closes_and_keeps_the_jacobi_integral():
    R, x0, GM = 6.778e6, 100.0, 3.986004418e14
    sol, t, y = motion("4.33", R=R, x0=x0, GM=GM)
    v0 = out(sol, "v0")
    assert t[0] == 0.0 and np.allclose(y[:, 0], [x0, 0, 0, v0], rtol=1e-15, atol=1e-15)
    W2 = GM / R**3
    x, yy, vx, vy = y
    # exact gravity relative to the satellite, in its rotating frame: Phi = -GM/|R + r| - GM x/R^2 - W^2 r^2/2,
    # the constant -GM/R taken out without cancellation
    d = np.sqrt((R + x) ** 2 + yy**2)
    phi = GM * (2 * R * x + x * x + yy * yy) / (R * d * (d + R)) - GM * x / R**2 - 0.5 * W2 * (x * x + yy * yy)
    J = 0.5 * (vx**2 + vy**2) + phi
    assert np.max(np.abs(J - J[0])) < 1e-7 * W2 * x0 * x0
    assert np.allclose(y[:, -1], y[:, 0], rtol=0, atol=1e-6 * x0 * math.sqrt(W2) + 1e-6 * x0)
    assert np.max(np.abs(yy)) == pytest.approx(out(sol, "a_along"), rel=1e-5)
    assert t[-1] == pytest.approx(out(sol, "T_rel"), rel=1e-9)


def test_4_34_the_pitch_libration_keeps_the_jacobi_integral():
    R, GM, amp = 7.0e6, 3.986004418e14, math.radians(10)
    sol, t, y = motion("4.34", R=R, GM=GM, theta_amp=amp)
    W2 = GM / R**3
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(amp, rel=1e-14) and y[1, 0] == 0.0
    # Hill's frame: potential -(3/2) W^2 x^2 for the end mass at x = l cos theta (Coriolis does no work):
    # theta'^2 = 3 W^2 (cos^2 theta - cos^2 amp)
    assert np.allclose(y[1] ** 2, 3 * W2 * (np.cos(y[0]) ** 2 - math.cos(amp) ** 2), rtol=0, atol=1e-8 * W2)
    assert abs(y[0, -1]) < 1e-10 and t[-1] == pytest.approx(out(sol, "T_pitch") / 4, rel=1e-9)


def test_4_34_no_libration_at_zero_amplitude_says_why(tmp_path):
    res = CliRunner().invoke(cli, ["solve", "4.34", "--theta_amp", "0", "--trajectory", str(tmp_path / "x.csv")])
    assert res.exit_code == 0 and "followed no motion at these parameters" in res.output
    assert not (tmp_path / "x.csv").exists()


def test_5_2_the_pulse_circles_q_st_then_the_free_swing_has_the_amplitude_after():
    m, w0, F0, T = 0.2, 5.0, 0.3, 0.4
    sol, t, y = motion("5.2", m=m, omega0=w0, F0=F0, T=T, t1=2.0)
    qst = F0 / (m * w0 * w0)
    assert t[0] == 0.0 and np.allclose(y[:, 0], 0.0, atol=0)
    q, v = y
    on = t <= T
    assert np.allclose((q[on] - qst) ** 2 + (v[on] / w0) ** 2, qst * qst, rtol=1e-8)
    off = t >= T
    assert np.allclose(np.hypot(q[off], v[off] / w0), out(sol, "A_after"), rtol=1e-8)
    assert t[-1] == pytest.approx(T + 2 * math.pi / w0, rel=1e-12)


def test_5_4_the_overdamped_relaxation_follows_its_two_exponentials():
    w0, z, q0 = 5.0, 2.0, 0.1
    sol, t, y = motion("5.4", omega0=w0, zeta=z, q0=q0, t1=1.0, eps=0.01)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [q0, 0.0], atol=0)
    # q = q0 (l+ e^(-l- t) - l- e^(-l+ t))/(l+ - l-), l+- = omega0 (zeta +- (zeta^2 - 1)^(1/2)): from rest at q0
    lp, lm = w0 * (z + math.sqrt(z * z - 1)), w0 * (z - math.sqrt(z * z - 1))
    q = q0 * (lp * np.exp(-lm * t) - lm * np.exp(-lp * t)) / (lp - lm)
    assert np.allclose(y[0], q, rtol=1e-7, atol=1e-10 * q0)
    assert t[-1] == pytest.approx(out(sol, "t_eps"), rel=1e-8) and y[0, -1] == pytest.approx(0.01 * q0, rel=1e-8)


def test_5_5_the_ringdown_is_a_damped_cosine():
    w0, d = 2764.601535159018, 1.5
    sol, t, y = motion("5.5", omega0=w0, delta=d, t1=0.25)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [1.0, 0.0], atol=0)
    wp = math.sqrt(w0 * w0 - d * d)
    x = np.exp(-d * t) * (np.cos(wp * t) + d / wp * np.sin(wp * t))  # from rest at q(0)
    assert np.allclose(y[0], x, rtol=0, atol=1e-7)
    assert t[-1] == pytest.approx(1.25 * 2 * math.pi / wp, rel=1e-6)


@pytest.mark.parametrize("theta0", [math.pi / 3, math.radians(170)])
def test_5_6_the_pendulum_keeps_its_energy_on_the_quarter_swing(theta0):
    l, g = 1.0, 9.81
    sol, t, y = motion("5.6", theta0=theta0, l=l, g=g)
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(theta0, rel=1e-15) and y[1, 0] == 0.0
    assert np.allclose(y[1] ** 2, 2 * g / l * (np.cos(y[0]) - math.cos(theta0)), rtol=0, atol=1e-8 * g / l)
    assert abs(y[0, -1]) < 1e-10 and y[1, -1] < 0
    assert t[-1] == pytest.approx(out(sol, "T") / 4, rel=1e-9)


@pytest.mark.parametrize("alpha", [0.8, -15.0])  # hardening; softening next to the barrier (other variables)
def test_5_7_the_duffing_oscillator_keeps_its_energy_on_the_quarter_period(alpha):
    w0, A = 2.0, 0.5
    sol, t, y = motion("5.7", omega0=w0, alpha=alpha, A=A)
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(A, rel=1e-14) and y[1, 0] == 0.0
    q, v = y
    E = 0.5 * v * v + 0.5 * w0 * w0 * q * q + 0.25 * alpha * q**4  # per unit mass, force -w0^2 q - alpha q^3
    E0 = 0.5 * w0 * w0 * A * A + 0.25 * alpha * A**4
    assert np.allclose(E, E0, rtol=1e-8)
    assert abs(q[-1]) < 1e-10 * A and t[-1] == pytest.approx(0.5 * math.pi / out(sol, "omega"), rel=1e-9)


def test_5_9_one_period_of_the_limit_cycle_closes_at_its_amplitude():
    w0, mu, beta = 3.0, 0.3, 4.0
    sol, t, y = motion("5.9", omega0=w0, mu=mu, beta=beta)
    A = out(sol, "A")
    assert t[0] == 0.0 and y[0, 0] == pytest.approx(A, rel=1e-9) and y[1, 0] == 0.0
    assert np.allclose(y[:, -1], y[:, 0], rtol=0, atol=1e-7 * A * w0)
    assert np.max(np.abs(y[0])) == pytest.approx(A, rel=1e-6)
    assert t[-1] == pytest.approx(2 * math.pi / out(sol, "omega"), rel=1e-9)


def test_5_9_a_relaxation_oscillation_starts_from_twice_the_small_swing_amplitude():
    sol, t, y = motion("5.9", omega0=3.0, mu=30.0, beta=4.0)
    assert t[0] == 0.0 and np.allclose(y[:, 0], [2 / math.sqrt(4.0), 0.0], atol=0)
    # it settles onto the cycle: its last extremum has the cycle's amplitude
    assert abs(y[0, -1]) == pytest.approx(out(sol, "A"), rel=1e-6)


def test_5_12_the_stationary_swing_repeats_after_two_pivot_periods():
    Om = 8.9
    sol, t, y = motion("5.12", l=0.5, g=9.81, delta=0.05, a=0.008, Omega=Om)
    assert t[0] == 0.0 and np.allclose(y[:, -1], y[:, 0], rtol=1e-7, atol=1e-9)
    # the samples straddle the turning points: their largest |theta| is below theta_st by at most
    # (w dt)^2/2 of it, w ~ Omega/2 the swing's frequency
    top, dt = out(sol, "theta_st"), np.max(np.diff(t))
    assert top * (1 - (0.5 * Om * dt) ** 2) <= np.max(np.abs(y[0])) <= top * (1 + 1e-8)
    assert t[-1] == pytest.approx(4 * math.pi / Om, rel=1e-12)


def test_every_exercise_with_states_has_its_motion_tested():
    """Here (a ``test_4_15_...``) or in the exercise's own test file, which then reads ``.trajectory``."""
    here = {name.split("_", 1)[1] for name in globals() if re.match(r"test_\d+_\d+_", name)}
    tests = pathlib.Path(__file__).parent
    for ex_id, ex in registry.all_exercises().items():
        if not ex.states or any(h.startswith(ex_id.replace(".", "_") + "_") for h in here):
            continue
        own = tests / f"test_ex{ex_id.replace('.', '_')}.py"
        assert own.exists() and ".trajectory" in own.read_text("utf-8"), f"{ex_id}: its motion is tested nowhere"


def test_the_api_hands_out_one_trajectory_type():
    # one typed Trajectory in the API: mech.Trajectory is Solution.trajectory's declared type and what it
    # returns; the integrator's own result (ode.Trajectory, one leg with its cost) is never handed out
    import typing

    from mech.solvers.numerics import ode
    from mech.verification import result

    assert mech.Trajectory is mech.api.Trajectory is result.Trajectory
    hints = typing.get_type_hints(result.Solution.trajectory.func, vars(result))
    assert hints["return"] == typing.Optional[result.Trajectory]
    sol, t, y = motion("4.15", theta0="60deg")
    tr = sol.trajectory
    assert type(tr) is mech.Trajectory and not isinstance(tr, ode.Trajectory)
    assert not any(v is ode.Trajectory for m in (mech, mech.api) for v in vars(m).values())
    # by hand: the ladder leaves the wall at asin((2/3) sin 60deg) = asin(1/sqrt 3): where the motion ends
    assert y[0, 0] == pytest.approx(math.radians(60), rel=1e-6)
    assert y[0, -1] == pytest.approx(math.asin(1 / math.sqrt(3)), rel=1e-6)
