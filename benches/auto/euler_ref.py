# Independent reference for the end of AUTO's post-buckled Euler branch (tip rotation 170 deg):
# IVP from the tip (r = 0, q = rotation by theta about e2, n_b = R^T (0, 0, -P), m_b = 0) backwards
# to s = 0, secant on P until the clamp angle 2 atan2(q2(0), q0(0)) vanishes. Same ODEs and
# stiffnesses as euler.f90 (K_b2 = 1 governs the planar branch), RK4, N and 2N steps.
import math, sys
sys.path.insert(0, __file__.rsplit('/', 1)[0])
import follower_ref as fr   # rod ODE f(y) and rot(q); K_b1 does not enter planar solutions
def clamp_angle(P, th, N):
    c, s = math.cos(math.radians(th) / 2), math.sin(math.radians(th) / 2)
    q = [c, 0.0, s, 0.0]; R = fr.rot(q)
    nb = [-P * R[2][i] for i in range(3)]            # R^T (0,0,-P)
    y = [0, 0, 0] + q + nb + [0, 0, 0]; h = -1.0 / N
    for _ in range(N):
        k1 = fr.f(y); k2 = fr.f([y[i] + h/2*k1[i] for i in range(13)])
        k3 = fr.f([y[i] + h/2*k2[i] for i in range(13)]); k4 = fr.f([y[i] + h*k3[i] for i in range(13)])
        y = [y[i] + h/6*(k1[i] + 2*k2[i] + 2*k3[i] + k4[i]) for i in range(13)]
    return 2 * math.atan2(y[5], y[3]), [-y[0], -y[1], -y[2]]
def solve(th, N):
    a, b = 14.6, 14.7
    fa = clamp_angle(a, th, N)[0]
    for _ in range(30):
        fb, r = clamp_angle(b, th, N)
        if abs(fb) < 1e-15: break
        a, b, fa = b, b - fb * (b - a) / (fb - fa), fb
    return b, r
if __name__ == "__main__":
    N = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    (P1, r1), (P2, r2) = solve(170.0, N), solve(170.0, 2 * N)
    print(f"theta=170 P={P2:.12f} x={r2[0]:.12f} z={r2[2]:.12f}  |N vs 2N|: P {abs(P1-P2):.1e} r {max(abs(r1[i]-r2[i]) for i in range(3)):.1e}")
