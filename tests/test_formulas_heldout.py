"""Held-out student formulas, judged as a careful instructor would (issue 24).

Every formula here was written from the physics by hand (textbook results re-derived for this file:
moments of inertia from their integrals, small-oscillation frequencies from T and U, energy and
angular-momentum balances), never read off mech's solvers.  Right ones come in several equivalent
forms (factored, expanded, with symbols, with aliases); each wrong one has exactly one slip: a
constant factor, a sign, a dependence right only at special values, a missing parameter, a wrong
dimension, or the leading-order approximation of an exact answer.  A pure slip must be named; "the
leading-order approximation" is said only of one the exercise declares (5.5, 5.6, 5.7), any other
limit form "agrees only in the limit of ..." (issue 31).

Each exercise is cross-checked once (mech's reference at the defaults), then all its formulas are
judged through the answers judge, as ``mech solve --expect`` does.
"""

from __future__ import annotations

import pytest

from mech.students import expectations as expecting
from mech.problems import registry
from mech.students.answers import judge
from mech.verification.crosscheck import cross_check

R = None  # right: no hint expected

# (output, formula, expected): expected is R for right, else a phrase the verdict must contain
CASES: dict[str, list[tuple[str, str, str | None]]] = {
    "4.1": [  # thin hoop: I_axis = M R^2, I_diam = half; disk: half of those; shell 2/3; ball 2/5
        ("I_hoop_axis", "M*R^2", R), ("I_hoop_diam", "M*R^2/2", R), ("I_hoop_diam", "0.5*M*R**2", R),
        ("I_disk_axis", "M R^2/2", R), ("I_disk_diam", "R^2*M/4", R),
        ("I_shell", "2/3*M*R^2", R), ("I_ball", "0.4*M*R^2", R), ("I_ball", "(2/5)*M*R*R", R),
        ("I_ball", "2/3*M*R^2", "I_shell"),
        ("I_ball", "2/5*M*R", "dimension"),
    ],
    "4.2": [  # rod triangle of side a: each rod M/3; plate M a^2/24 in plane; tetrahedron M a^2/20
        ("I_rods_normal", "M*a^2/6", R), ("I_rods_inplane", "M*a^2/12", R),
        ("I_plate_normal", "M*a^2/12", R), ("I_tetra", "M*a^2/20", R), ("I_tetra", "0.05*M*a^2", R),
        ("I_rods_normal", "M*a^2/12", "factor 1/2"),
    ],
    "4.3": [  # right triangle legs a, b: about the centroid, normal axis M (a^2+b^2)/18
        ("I3", "M*(a^2+b^2)/18", R), ("I3", "M*a^2/18 + M*b^2/18", R),
        ("I3", "M*(a^2+b^2)/12", "factor 3/2"),
        ("I3", "M*a^2/9", "b"),
    ],
    "4.4": [  # rod of length l tilted by beta from the axis, centre at distance d from it
        ("I_axis", "M*(d^2 + l^2*sin(beta)^2/12)", R), ("I_axis", "M*d^2 + M*l^2*(1-cos(2*beta))/24", R),
        ("Lz", "M*(d^2 + l^2*sin(β)^2/12)*ω", R),
        ("T", "M*(d^2 + l^2*sin(beta)^2/12)*omega^2/2", R),
        ("L_perp", "M*l^2*abs(omega)*sin(beta)*cos(beta)/12", R),
        ("L_perp", "M*l^2*abs(omega)*sin(2*beta)/24", R),
        ("I_axis", "M*(d^2 + l^2/12)", "beta"),
        ("T", "M*(d^2 + l^2*sin(beta)^2/12)*omega^2", "factor 2"),
    ],
    "4.5": [  # cone: M = pi rho R^2 H / 3; rolling: omega = Omega H / R with Omega = 2 pi f
        ("M", "pi*rho*R^2*H/3", R), ("omega", "2*pi*f*H/R", R), ("omega", "2 pi f H / R", R),
        ("M", "pi*rho*R^2*H", "factor 3"),
        ("omega", "2*pi*f", "H"),
    ],
    "4.6": [  # differential: the carrier turns at the mean rate; each half-shaft takes half the torque
        ("omega_c", "(omega1+omega2)/2", R), ("omega_c", "(ω₁ + ω₂)/2", R), ("tau1", "tau/2", R),
        ("P1", "tau*omega1/2", R), ("P2", "0.5*tau*omega2", R),
        ("P1", "tau*omega1", "factor 2"),
        ("omega_c", "(omega1-omega2)/2", "omega2"),
    ],
    "4.7": [  # momentum and angular momentum about the centre with a rod of mass m, length l, bullet m_b
        ("v_hit", "4*m_b*v0/(m+4*m_b)", R), ("v_hit", "4*m'*v0/(m+4*m')", R),
        ("omega", "3*m_b*v0/(l*(m+4*m_b))", R), ("v_end", "-2*m_b*v0/(m+4*m_b)", R),
        ("E_loss", "m_b*v0^2/2*m/(m+4*m_b)", R),
        ("v_end", "2*m_b*v0/(m+4*m_b)", "wrong sign"),
        ("omega", "3*m_b*v0/(l*m)", "only in the limit of small m_b"),
    ],
    "4.8": [  # cue hit at height h: the final rolling speed 5 P h / (7 M R) whatever b
        ("V_f", "5*P*h_over_R/(7*M)", R), ("V_f", "5*P*(h/R)/(7*M)", R),
        ("omega_z", "-5*b_over_R*P/(2*M*R)", R),
        ("V_f", "5*P/(7*M)", "h_over_R"),
        ("V_f", "5*P*h_over_R/(7*M*R)", "dimension"),
    ],
    "4.9": [  # rolling cylinder, centre of mass l off its axis: I_contact = I + M (R - l)^2 at the bottom
        ("Omega", "sqrt(M*g*l/(I+M*(R-l)^2))", R), ("period", "2*pi*sqrt((I+M*(R-l)^2)/(M*g*l))", "small phi0"),
        ("Omega", "sqrt(M*g*l/(I+M*R^2))", "l"),
    ],
    "4.10": [  # physical pendulum: Omega^2 = M g l / (I + M l^2)
        ("Omega", "sqrt(M*g*l/(I+M*l^2))", R), ("Omega", "(M g l/(I + M l^2))^(1/2)", R),
        ("l_ef", "l + I/(M*l)", R), ("l_opt", "sqrt(I/M)", R), ("l_conj", "I/(M*l)", R),
        ("Omega", "sqrt(g/l)", "I"),
        ("Omega", "sqrt(M*g*l/(I+M*l^2))/(2*pi)", "factor 1/(2 pi)"),
    ],
    "4.11": [  # the block's spring against the block plus a third of the cylinder's mass
        ("omega", "sqrt(kappa/(M_prime+M/3))", R), ("omega", "sqrt(κ/(M' + M/3))", R),
        ("omega", "sqrt(kappa/(M_prime+M))", "M"),
    ],
    "4.12": [  # chime: l l' w^4 - g (4 l + 6 l') w^2 + 6 g^2 = 0
        ("omega1", "sqrt(g*(2*l+3*l_prime-sqrt(4*l^2+6*l*l_prime+9*l_prime^2))/(l*l_prime))", R),
        ("omega2", "sqrt(g*(2*l+3*l_prime+sqrt(4*l^2+6*l*l_prime+9*l_prime^2))/(l*l_prime))", R),
        ("omega1", "sqrt(g*(2*l+3*l_prime+sqrt(4*l^2+6*l*l_prime+9*l_prime^2))/(l*l_prime))", "omega2"),
    ],
    "4.13": [  # cylinder in a hollow of a free block: rho = R' - R
        ("omega", "sqrt(2*g*(M+M_prime)/((R_prime-R)*(M+3*M_prime)))", R),
        ("omega", "sqrt(2*g/(R_prime-R)*(M+M_prime)/(M+3*M_prime))", R),
        ("omega", "sqrt(2*g/(3*(R_prime-R)))", "M_prime"),
    ],
    "4.14": [  # solid hemisphere: centre of mass 3R/8 from the flat face
        ("d_cm", "3*R/8", R), ("omega_rolling", "sqrt(15*g/(26*R))", R),
        ("omega_frictionless", "sqrt(120*g/(83*R))", R),
        ("d_cm", "3*R/5", "factor 8/5"),
        ("omega_rolling", "sqrt(15*g*R/26)", "dimension"),
    ],
    "4.15": [  # energy: theta'^2 = (3g/l)(sin theta0 - sin theta); the wall's push vanishes at 2/3 sin theta0
        ("theta_c", "asin(2/3*sin(theta0))", R), ("theta_c", "arcsin(2*sin(θ₀)/3)", R),
        ("theta_c", "atan2(2*sin(theta0), sqrt(9-4*sin(theta0)^2))", R),
        ("omega_c", "sqrt(g*sin(theta0)/l)", R), ("omega_c", "(g/l)^0.5*sqrt(sin(theta0))", R),
        ("theta_c", "asin(2/3)", "theta0"),
        ("omega_c", "sqrt(g*l)", "dimension"),
        ("theta_c", "asin(1.2*sin(theta0))", "asin of"),
        ("omega_c", "sqrt(2*g*sin(theta0)/l)", "sqrt(2)"),
    ],
    "4.16": [  # hexagon of six rods, pushed at one side
        ("a", "10*F/(33*m)", R), ("a_prime", "F/(33*m)", R), ("alpha_adj", "3*F/(11*m*l)", R),
        ("a", "F/(6*m)", "factor 11/20"),
    ],
    "4.17": [  # body frame, omega along the diagonal: tau = omega x (I omega), I_1 = rho V (a2^2 + a3^2)/12
        ("tau3", "rho*a1*a2*a3*omega^2/(12*(a1^2+a2^2+a3^2))*a1*a2*(a1^2-a2^2)", R),
        ("tau3", "rho*a1*a2*a3*omega^2/(12*(a1^2+a2^2+a3^2))*a1*a2*(a2^2-a1^2)", "wrong sign"),
        ("tau3", "rho*a1*a2*a3*omega/(12*(a1^2+a2^2+a3^2))*a1*a2*(a1^2-a2^2)", "dimension"),
    ],
    "4.18": [  # ball on a turntable: its centre circles at 2 Omega / 7
        ("omega_orbit", "2*Omega/7", R), ("r_orbit", "7*sqrt(vx0^2+vy0^2)/(2*Omega)", R),
        ("xc", "x0 - 7*vy0/(2*Omega)", R), ("yc", "y0 + 7*vx0/(2*Ω)", R),
        ("omega_orbit", "Omega", "factor 7/2"),
    ],
    "4.19": [  # thin disk: I3 = 2 I1; the body sees omega cos alpha, the lab omega (1 + 3 cos^2 alpha)^1/2
        ("Omega_body", "omega*cos(alpha)", R), ("omega_lab", "omega*sqrt(1+3*cos(alpha)^2)", R),
        ("theta_L", "atan(tan(alpha)/2)", R),
        ("omega_lab", "2*omega", "small alpha"),
    ],
    "4.20": [  # Euler's equations linearised about each principal axis
        ("Omega_1", "omega0*sqrt((I2-I1)*(I3-I1)/(I2*I3))", R),
        ("lambda_2", "omega0*sqrt((I2-I1)*(I3-I2)/(I1*I3))", R),
        ("Omega_3", "omega0*sqrt((I3-I1)*(I3-I2)/(I1*I2))", R),
        ("lambda_2", "omega0*sqrt((I2-I1)*(I3-I2)/(I2*I3))", "I"),
    ],
    "4.21": [  # sleeping-top threshold with I_A = I1 + M l^2 about the tip
        ("omega_th", "2*sqrt((I1+M*l^2)*M*g*l)/I3", R),
        ("omega_th", "2*sqrt(I1*M*g*l)/I3", "l"),
    ],
    "4.22": [  # rolling disk on a shaft: the gyroscopic torque adds M R Omega^2 / 2 to the weight
        ("N", "M*g + M*R*Omega^2/2", R), ("delta_N", "M*R*Omega^2/2", R), ("omega_spin", "Omega*l/R", R),
        ("delta_N", "-M*R*Omega^2/2", "wrong sign"),
        ("N", "M*g", "Omega"),
    ],
    "4.23": [  # rolling coin: Omega^2 = 4 g tan(theta) / (6 R - 5 r sin(theta))
        ("Omega", "sqrt(4*g*tan(theta)/(6*R-5*r*sin(theta)))", R),
        ("T", "pi*sqrt((6*R-5*r*sin(theta))/(g*tan(theta)))", R),
        ("Omega", "sqrt(2*g*tan(theta)/(3*R))", "only in the limit of small r"),
    ],
    "4.24": [  # fast top: the axis turns by pi/2 in t_down = pi L3 / (2 l F), L3 = I3 omega_rot
        ("t_down", "pi*I3*omega_rot/(2*l*F)", R), ("t_up", "3*pi*I3*omega_rot/(2*l*F)", R),
        ("t_down", "I3*omega_rot/(l*F)", "factor 2/pi"),
    ],
    "4.25": [  # friction at the tip: constant spin-down, rise rate mu M g l / L3
        ("omega_dot", "mu*M*g*R/I3", R), ("theta_dot0", "mu*M*g*l/(I3*omega0)", R),
        ("omega_rise", "omega0*exp(-(theta0-theta1)*R/l)", R),
        ("t_rise", "omega0*I3*(1-exp(-(theta0-theta1)*R/l))/(mu*M*g*R)", R),
        ("omega_rise", "omega0*exp((theta0-theta1)*R/l)", "theta"),
        ("omega_dot", "mu*M*g*R/I3^2", "dimension"),
    ],
    "4.26": [  # balloon (massless) in water: its acceleration relative to the container
        ("ratio", "2*(b^3-a^3)/(b^3+2*a^3)", R),
        ("a_container", "F/(Mc + 4*pi/3*rho*b^3*(b^3-a^3)/(b^3+2*a^3))", R),
        ("a_container", "F/(Mc + 4*pi/3*rho*b^3)", "small a"),
    ],
    "4.27": [  # Hill sphere: the leading order of the quintic's root for small M2/M1
        ("r_L1", "d*(M2/(3*M1))^(1/3)", "only in the limit of small M2"),
    ],
    "4.28": [  # equilateral triangle with the two bodies, from the centre of mass
        ("x_L4", "d*(1/2 - M2/(M1+M2))", R), ("x_L4", "d*(M1-M2)/(2*(M1+M2))", R),
        ("y_L4", "sqrt(3)/2*d", R),
        ("x_L4", "d/2", "M"),
    ],
    "4.29": [  # bead on a rod turning at omega: r'' = omega^2 r
        ("r", "r0*cosh(omega*t) + v0/omega*sinh(omega*t)", R),
        ("r", "(r0+v0/omega)/2*exp(omega*t) + (r0-v0/omega)/2*exp(-omega*t)", R),
        ("a_rot", "omega^2*(r0*cosh(omega*t) + v0/omega*sinh(omega*t))", R),
        ("r", "r0*exp(omega*t)", "v0"),
    ],
    "4.30": [  # Foucault: the plane turns at -omega_E cos(theta) (theta from the north pole)
        ("Omega_F", "-omega_E*cos(theta)", R), ("T_F", "2*pi/(omega_E*abs(cos(theta)))", R),
        ("b_miss", "a*omega_E*abs(cos(theta))/sqrt(g/l+omega_E^2*cos(theta)^2)", R),
        ("Omega_F", "omega_E*cos(theta)", "wrong sign"),
        ("b_miss", "a*omega_E*abs(cos(theta))*sqrt(l/g)", "only in the limit"),
    ],
    "4.31": [  # eastward deflection: exact in omega_E t only through the model's closed form
        ("d_east", "2*sqrt(2)/3*omega_E*sin(theta)*h^1.5/sqrt(g)", "only in the limit"),
    ],
    "4.32": [  # tidal bulge to leading order in R_E / r_S: h_high = (M_S/M_E) R_E^4 / r_S^3
        ("h_high", "M_S/M_E*R_E^4/r_S^3", "only in the limit"),
        ("h_range", "M_S/M_E*R_E^3/r_S^3", "dimension"),
    ],
    "4.33": [  # Hill frame around a circular orbit: Omega = sqrt(GM / R^3)
        ("T_rel", "2*pi*sqrt(R^3/GM)", R), ("T_rel", "2*pi/sqrt(GM/R^3)", R), ("a_radial", "abs(x0)", R),
        ("v0", "-2*sqrt(GM/R^3)*x0", "only in the limit"),
        ("T_rel", "sqrt(R^3/GM)", "1/(2 pi)"),
    ],
    "4.34": [  # gravity gradient: pitch sqrt(3) Omega, roll 2 Omega, Omega^2 = GM / R^3
        ("omega_pitch", "sqrt(3*GM/R^3)", R), ("omega_roll", "2*sqrt(GM/R^3)", R),
        ("omega_pitch", "sqrt(GM/R^3)", "sqrt(3)"),
    ],
    "4.35": [  # falling rod: bending torque m g l sin(theta) xi (1 - xi)^2 / 4
        ("tau", "m*g*l*sin(theta)/4*xi*(1-xi)^2", R), ("s_max", "l/3", R),
        ("tau_max", "m*g*l*sin(theta)/27", R),
        ("tau_max", "m*g*l/27", "theta"),
    ],
    "4.36": [  # L = m (v + v0)^2 / 2 - k x^2 / 2 in a frame moving at v0 (accelerating at a0)
        ("p", "m*(v+v0)", R), ("H", "m*(v^2-v0^2)/2 + k*x^2/2", R), ("E", "m*(v+v0)^2/2 + k*x^2/2", R),
        ("a", "-k*x/m - a0", R),
        ("p", "m*v", "v0"),
    ],
    "5.1": [  # chi = 1 / (m (omega0^2 - omega^2 - 2 i delta omega))
        ("chi_re", "(omega0^2-omega^2)/(m*((omega0^2-omega^2)^2+4*delta^2*omega^2))", R),
        ("chi_im", "2*delta*omega/(m*((omega0^2-omega^2)^2+4*delta^2*omega^2))", R),
        ("chi_im", "-2*delta*omega/(m*((omega0^2-omega^2)^2+4*delta^2*omega^2))", "wrong sign"),
    ],
    "5.2": [  # after the pulse: amplitude 2 |q_st| |sin(omega0 T / 2)|, q_st = F0 / (m omega0^2)
        ("A_after", "2*abs(F0)/(m*omega0^2)*abs(sin(omega0*T/2))", R),
        ("A_after", "abs(F0)/(m*omega0^2)*sqrt(2-2*cos(omega0*T))", R),
        ("A_after", "2*abs(F0)/(m*omega0^2)", "T"),
    ],
    "5.3": [  # steady-state amplitude of a driven damped oscillator
        ("A_ss", "abs(F0)/m/sqrt((omega0^2-omega^2)^2+4*delta^2*omega^2)", R),
        ("A_ss", "abs(F0)/m/sqrt((omega0^2-omega^2)^2+delta^2*omega^2)", "delta"),
    ],
    "5.4": [  # overdamped: the slow root of s^2 + 2 zeta omega0 s + omega0^2
        ("lambda_slow", "omega0*(zeta - sqrt(zeta^2-1))", R), ("lambda_slow", "omega0/(zeta + sqrt(zeta^2-1))", R),
        ("lambda_slow", "omega0*(zeta + sqrt(zeta^2-1))", "zeta"),
    ],
    "5.5": [  # Q = omega0 / (2 delta); the energy loss per cycle exp(-2 delta T_d)
        ("Q", "omega0/(2*delta)", R), ("bandwidth", "2*delta", "approximation"),
        ("loss_per_cycle", "1 - exp(-4*pi*delta/sqrt(omega0^2-delta^2))", R),
        ("loss_per_cycle", "4*pi*delta/omega0", "small delta"),
        ("Q", "omega0/delta", "factor 2"),
    ],
    "5.6": [  # the small-amplitude period of a pendulum is only the leading order
        ("T", "2*pi*sqrt(l/g)", "small theta0"), ("T_ratio", "1 + theta0^2/16", "small theta0"),
    ],
    "5.7": [  # Duffing: first-order frequency shift 3 alpha A^2 / (8 omega0)
        ("omega", "omega0 + 3*alpha*A^2/(8*omega0)", "approximation"),
        ("domega", "3*alpha*A^2/(8*omega0)", "approximation"),
    ],
    "5.8": [  # reduced equations: A_max = f0 / (2 omega0 delta), xi_peak = kappa A_max^2
        ("A_max", "f0/(2*omega0*delta)", R), ("xi_peak", "3*alpha*f0^2/(32*omega0^3*delta^2)", R),
        ("A_max", "f0/(omega0*delta)", "factor 2"),
    ],
    "5.9": [  # van der Pol: A = 2 / sqrt(beta), omega = omega0, lambda = -mu
        ("A", "2/sqrt(beta)", R), ("A", "sqrt(4/β)", R), ("omega", "omega0", R), ("lambda_lc", "-mu", R),
        ("A", "2/beta", "dimension"), ("lambda_lc", "mu", "wrong sign"),
    ],
    "5.10": [  # Adler: Delta = f0 sqrt(beta) / (4 omega0); the locking band is 2 Delta wide
        ("width", "f0*sqrt(beta)/(2*omega0)", R), ("xi_hi", "f0*sqrt(beta)/(4*omega0)", R),
        ("xi_lo", "-f0*sqrt(beta)/(4*omega0)", R),
        ("width", "f0*sqrt(beta)/(4*omega0)", "factor 1/2"),
    ],
    "5.11": [  # Mathieu: threshold (4/omega0) sqrt(delta^2 + (omega - omega0)^2)
        ("mu_th", "4/omega0*sqrt(delta^2+(omega-omega0)^2)", R),
        ("mu_th", "4*delta/omega0", "omega"),
    ],
    "5.12": [  # pumped pendulum: a_th = (2 l / Omega) sqrt(delta^2 + (Omega/2 - sqrt(g/l))^2)
        ("a_th", "2*l/Omega*sqrt(delta^2+(Omega/2-sqrt(g/l))^2)", R),
        ("a_th", "2*l*delta/Omega", "g"),
    ],
    "5.13": [  # Kapitza: the inverted position is stable above a_min = sqrt(2 g l) / Omega
        ("a_min", "sqrt(2*g*l)/Omega", R), ("omega_down", "sqrt(g/l + a^2*Omega^2/(2*l^2))", R),
        ("a_min", "sqrt(g*l)/Omega", "1/sqrt(2)"),
    ],
}


def _own_cases() -> dict[str, list]:
    """Held-out formulas an exercise's own test file carries (``HELDOUT_FORMULAS``, same tuples as CASES):
    where an exercise added after this set keeps its own, so that adding one touches only its files."""
    import importlib.util
    from pathlib import Path

    found = {}
    for ex_id in registry.all_exercises():
        path = Path(__file__).with_name(f"test_ex{ex_id.replace('.', '_')}.py")
        if ex_id in CASES or not path.exists() or "HELDOUT_FORMULAS" not in path.read_text("utf-8"):
            continue
        spec = importlib.util.spec_from_file_location(f"_heldout_{path.stem}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        found[ex_id] = list(module.HELDOUT_FORMULAS)
    return found


ALL_CASES = {**CASES, **_own_cases()}


def test_the_set_covers_30_exercises_and_every_family():
    """Every registered exercise (each its own topic) has held-out formulas, here or in its own test."""
    assert len(CASES) >= 30
    topics = {registry.get(i).topic for i in registry.all_exercises()}
    assert {registry.get(i).topic for i in ALL_CASES} == topics


@pytest.mark.parametrize("ex_id", sorted(ALL_CASES, key=lambda s: tuple(map(int, s.split(".")))))
def test_heldout_formulas(ex_id):
    ex = registry.get(ex_id)
    result = cross_check(ex, ex.resolve({}))
    cases = ALL_CASES[ex_id]
    expectations = [expecting.parse_expectation(ex, out, text) for out, text, _ in cases]
    assert [text for (_, text, _), e in zip(cases, expectations) if e.formula is None] == []
    problems = []
    for (out, text, want), j in zip(cases, (judge(result, [e])[0] for e in expectations)):
        if want is None:
            if not j.match:
                problems.append(f"{out} = {text}: judged wrong: {j.verdict}")
        elif j.match:
            problems.append(f"{out} = {text}: judged right, but it has a slip ({want})")
        elif want.lower() not in j.verdict.lower():
            problems.append(f"{out} = {text}: the verdict does not name '{want}': {j.verdict}")
    assert not problems, "\n".join(problems)
