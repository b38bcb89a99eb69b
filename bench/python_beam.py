"""The reference beam in plain numpy, written as a numpy user would write it.

Shared by bench/compare_python_simulate.py and bench/compare_python_ident.py
(the Python peers of podid's simulator and `wavelet` objective; issues 2, 5).

Model (examples/beam.toml): clamped Euler-Bernoulli beam, 6 elements,
consistent mass, Rayleigh damping fitted to 1 % on modes 1-2 of the linear
beam, cubic spring f = -k3 w^3 at the tip's w dof (k3 = knl * 1e8), released
from the static tip deflection under 20 N (solved with the spring). Time
integration: Newmark average acceleration (gamma = 1/2, beta = 1/4), full
Newton on the residual each step (np.linalg.solve on the 12 x 12 tangent),
stopping at ||r||_inf <= 1e-10 * (force scale), like podid's tolerance.
"""
import numpy as np
import scipy.linalg

LENGTH = 0.593
ELEMENTS = 6
E = 2.05e11
RHO = 7800.0
AREA = 0.196e-3
SECOND_MOMENT = AREA ** 2 / 12.0  # square section
TIP_FORCE = 20.0
ZETA = (0.01, 0.01)


def assemble(elements=ELEMENTS):
    n_all = 2 * (elements + 1)
    l = LENGTH / elements
    ei = E * SECOND_MOMENT
    rho_a = RHO * AREA
    ke = ei / l ** 3 * np.array([[12, 6 * l, -12, 6 * l],
                                 [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                                 [-12, -6 * l, 12, -6 * l],
                                 [6 * l, 2 * l * l, -6 * l, 4 * l * l]])
    me = rho_a * l / 420.0 * np.array([[156, 22 * l, 54, -13 * l],
                                       [22 * l, 4 * l * l, 13 * l, -3 * l * l],
                                       [54, 13 * l, 156, -22 * l],
                                       [-13 * l, -3 * l * l, -22 * l, 4 * l * l]])
    k = np.zeros((n_all, n_all))
    m = np.zeros((n_all, n_all))
    for e in range(elements):
        k[2 * e:2 * e + 4, 2 * e:2 * e + 4] += ke
        m[2 * e:2 * e + 4, 2 * e:2 * e + 4] += me
    return m[2:, 2:], k[2:, 2:]  # clamp node 0


def rayleigh(m, k):
    w2 = scipy.linalg.eigh(k, m, eigvals_only=True)
    w1, w2 = np.sqrt(w2[0]), np.sqrt(w2[1])
    beta = 2.0 * (ZETA[1] * w2 - ZETA[0] * w1) / (w2 * w2 - w1 * w1)
    alpha = 2.0 * ZETA[0] * w1 - beta * w1 * w1
    return alpha * m + beta * k


def static_tip(k, k3, tip):
    f = np.zeros(k.shape[0])
    f[tip] = TIP_FORCE
    x = np.linalg.solve(k, f)
    for _ in range(50):
        r = k @ x - f
        r[tip] += k3 * x[tip] ** 3
        if np.linalg.norm(r) <= 1e-12 * TIP_FORCE:
            break
        kt = k.copy()
        kt[tip, tip] += 3 * k3 * x[tip] ** 2
        x -= np.linalg.solve(kt, r)
    return x


def simulate(knl, duration=1.0, dt=2e-4, elements=ELEMENTS):
    """Sensor displacements w1..w6 (samples x 6) of the free vibration."""
    m, k = assemble(elements)
    c = rayleigh(m, k)
    n = m.shape[0]
    tip = n - 2
    k3 = knl * 1e8
    steps = int(round(duration / dt))
    gamma, beta = 0.5, 0.25
    a0 = 1 / (beta * dt * dt)
    a1 = gamma / (beta * dt)
    a2 = 1 / (beta * dt)
    a3 = 1 / (2 * beta) - 1
    a4 = gamma / beta - 1
    a5 = dt * (gamma / (2 * beta) - 1)

    x = static_tip(k, k3, tip)
    v = np.zeros(n)
    fnl = np.zeros(n)
    fnl[tip] = -k3 * x[tip] ** 3
    a = np.linalg.solve(m, fnl - c @ v - k @ x)
    s = a0 * m + a1 * c + k
    sensors = np.arange(0, n, 2)
    out = np.empty((steps + 1, len(sensors)))
    out[0] = x[sensors]
    for i in range(steps):
        # Effective load of the linear part from the previous state.
        rhs = m @ (a0 * x + a2 * v + a3 * a) + c @ (a1 * x + a4 * v + a5 * a)
        scale = max(np.abs(rhs).max(), 1e-300)
        xn = x + dt * v + 0.25 * dt * dt * a  # predictor
        for _ in range(50):
            r = s @ xn - rhs
            r[tip] += k3 * xn[tip] ** 3
            if np.abs(r).max() <= 1e-10 * scale:
                break
            kt = s.copy()
            kt[tip, tip] += 3 * k3 * xn[tip] ** 2
            xn = xn - np.linalg.solve(kt, r)
        an = a0 * (xn - x) - a2 * v - a3 * a
        v = v + dt * ((1 - gamma) * a + gamma * an)
        x, a = xn, an
        out[i + 1] = x[sensors]
    return out
