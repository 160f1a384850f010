# Independent reference for the follower cantilever: the body-frame balance laws do not involve
# r, q, so integrate the 13 ODEs as an IVP backwards from s = L (r = 0, q = 1, n_b = (a,0,0),
# m_b = 0) and map the frame at s = 0 to the clamp. Classical RK4, N steps, Richardson check.
import math, sys
KB1, KB2, KT, GA, EA = 1.0, 1.0, 1/1.3, 1e4, 2.6e4
def rot(q):
    q0,q1,q2,q3 = q
    return [[q0*q0+q1*q1-q2*q2-q3*q3, 2*(q1*q2-q0*q3), 2*(q1*q3+q0*q2)],
            [2*(q1*q2+q0*q3), q0*q0-q1*q1+q2*q2-q3*q3, 2*(q2*q3-q0*q1)],
            [2*(q1*q3-q0*q2), 2*(q2*q3+q0*q1), q0*q0-q1*q1-q2*q2+q3*q3]]
def f(y):
    q = y[3:7]; n = y[7:10]; m = y[10:13]
    u = [m[0]/KB1, m[1]/KB2, m[2]/KT]; v = [n[0]/GA, n[1]/GA, 1+n[2]/EA]
    R = rot(q)
    rp = [sum(R[i][j]*v[j] for j in range(3)) for i in range(3)]
    q0,q1,q2,q3 = q; u1,u2,u3 = u
    qp = [0.5*(-q1*u1-q2*u2-q3*u3), 0.5*(q0*u1+q2*u3-q3*u2), 0.5*(q0*u2+q3*u1-q1*u3), 0.5*(q0*u3+q1*u2-q2*u1)]
    cr = lambda a,b: [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
    un = cr(u,n); um = cr(u,m); vn = cr(v,n)
    return rp + qp + [-x for x in un] + [-(um[i]+vn[i]) for i in range(3)]
def tip(a, N):
    y = [0,0,0, 1,0,0,0, a,0,0, 0,0,0]; h = -1.0/N
    for _ in range(N):
        k1 = f(y); k2 = f([y[i]+h/2*k1[i] for i in range(13)])
        k3 = f([y[i]+h/2*k2[i] for i in range(13)]); k4 = f([y[i]+h*k3[i] for i in range(13)])
        y = [y[i]+h/6*(k1[i]+2*k2[i]+2*k3[i]+k4[i]) for i in range(13)]
    r0 = y[0:3]; q0 = y[3:7]; R0 = rot(q0)
    rt = [-sum(R0[j][i]*r0[j] for j in range(3)) for i in range(3)]   # R0^T (0 - r0)
    qc = [q0[0], -q0[1], -q0[2], -q0[3]]                                # q(L) = q0^-1 o 1
    th = 2*math.degrees(math.atan2(qc[2], qc[0]))
    return rt, th
if __name__ == "__main__":
    N = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
    for a in [1.0, 2.0, 5.0, 10.0]:
        (r1, t1), (r2, t2) = tip(a, N), tip(a, 2*N)
        print(f"alpha={a:5.1f} x={r2[0]:.15f} y={r2[1]:.1e} z={r2[2]:.15f} theta={t2:.9f}  |RK4 N vs 2N|={max(abs(r1[i]-r2[i]) for i in range(3)):.1e}")
