// A small finite-element beam program of the kind users already have, with
// rodkit embedded the way an FE pipeline embeds it (issue 20, item 6).
//
// The program owns the solution procedure: its own load stepping (with a
// tangent predictor and step cutting), its own Newton loop with its own
// convergence test, and its own sparse LU with threshold partial pivoting
// (left-looking, Gilbert-Peierls, as in CSparse's cs_lu). rodkit supplies
// the physics only:
//   - the section law, from a helically reinforced tube: the 6x6 rod
//     stiffness of a thick orthotropic wall (rodkit_tube_rod_stiffness,
//     physics.md 1.4-1.5 "the effective rod law", 2.2 hemitropic rods);
//   - the discrete equations of the Cosserat rod (physics.md 2.1, 2.3:
//     Gauss-Legendre collocation) as plain kernels: rodkit_rod_residual,
//     rodkit_rod_jacobian (values, plus dR/dLambda for the predictor), with
//     the sparsity taken once from rodkit_rod_jacobian_pattern.
//
// Problem: a cantilever hose (fibre-reinforced elastomer tube, below),
// clamped at s = 0, under a DEAD tip force P = Lambda * K_b / L^2 along the
// global x axis (fixed in space as the tip rotates; physics.md 2.1 "dead":
// f_b = Lambda R(q)^T f), loaded in steps to Lambda = P L^2 / EI_eff = 5: a
// large deflection (tip rotation about 70 degrees).
//
// Checks (each prints its figures; the program exits 1 when one fails):
//   1. Agreement with rodkit's own solver: rodkit_rod_continue (ANM,
//      physics.md 2.4) on the same rod to the same Lambda. Both solve the
//      same discrete equations, so the tips agree to the solvers'
//      tolerances: |tip difference| / L and the tip rotation difference
//      must be below TIP_TOL = 1e-9.
//   2. A small-load step (Lambda = 1e-4) against linear beam theory with the
//      section's own stiffness, bend-shear coupling included (derived at
//      linear_theory() below). Collocation with 4 stages is exact for the
//      linearised problem (its solution is a cubic in s), so the difference
//      is the geometric nonlinearity, O(Lambda^2) relative (measured 1e-9):
//      LINEAR_TOL = 1e-7, far below the shear term's share (about 9e-4), which
//      the check therefore resolves; the bend-shear coupling c2 changes the
//      deflection by a factor of about 4 for this wall.
//
// Usage: cpp_fe_beam [--values] [elements] [load_steps]   (defaults 16 and 10;
//        --values adds every figure as a `name = value` line)
// Units: N, mm, MPa (N/mm^2).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rodkit.h"

namespace {

// Print the `name = value` lines too (--values).
bool g_values = false;

// ---------------------------------------------------------------------------
// rodkit statuses: every call is checked; < 0 is a failure (c-api.md).

struct RodkitFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

int32_t check(int32_t st, const char *what) {
    if (st < 0)
        throw RodkitFailure(std::string(what) + " failed: " + rodkit_status_string(st) + " (" +
                            std::to_string(st) + "): " + rodkit_last_error_message());
    return st;
}

// Owning wrappers, so every handle is freed on every path.
struct Tube {
    RodkitTube *p = nullptr;
    ~Tube() { rodkit_tube_free(p); }
};
struct Rod {
    RodkitRod *p = nullptr;
    ~Rod() { rodkit_rod_free(p); }
};
struct Branch {
    RodkitBranch *p = nullptr;
    ~Branch() { rodkit_branch_free(p); }
};

// ---------------------------------------------------------------------------
// The section: a helically reinforced hose wall (physics.md 1.1, 1.3 SVK).
// A fibre-reinforced elastomer (stiff cords in soft rubber, one helical
// family as in single-helix soft actuators), modelled as an orthotropic
// Saint Venant-Kirchhoff wall with axis 1 along the cords: E1 = 1 GPa along
// them, 20 MPa across, nu12 = nu13 = nu23 = 0.45, G12 = G13 = 5 MPa, G23
// isotropic in the transverse plane. Inner radius 10 mm, outer 13 mm
// (t/R = 0.26: thick, so the thick-wall model), cords at 30 degrees from the
// axis at the mid radius 11.5 mm (tau0 = tan 30deg / 11.5 mm; the angle
// varies through the wall, atan(tau0 R)).
struct Wall {
    double inner = 10.0, outer = 13.0;
    double tau0 = std::tan(M_PI / 6.0) / 11.5;
    double e1 = 1000.0, e2 = 20.0, e3 = 20.0;
    double nu12 = 0.45, nu13 = 0.45, nu23 = 0.45;
    double g12 = 5.0, g13 = 5.0, g23 = 20.0 / (2.0 * 1.45);
};

// The 6x6 section stiffness K, column-major, order (u1, u2, u3, v1, v2, v3)
// <-> (m1, m2, m3, n1, n2, n3) (physics.md 2.1), and its error estimate.
std::array<double, 36> section_stiffness(const Wall &w, double *estimate) {
    RodkitTubeSpec spec;
    check(rodkit_tube_spec_default(&spec), "rodkit_tube_spec_default");
    spec.inner_radius = w.inner;
    spec.outer_radius = w.outer;
    RodkitWallMaterialSpec &m = spec.material;
    m.law = RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF;
    m.incompressible = 0;
    m.intrinsic_twist = w.tau0;
    m.e1 = w.e1, m.e2 = w.e2, m.e3 = w.e3;
    m.nu12 = w.nu12, m.nu13 = w.nu13, m.nu23 = w.nu23;
    m.g12 = w.g12, m.g13 = w.g13, m.g23 = w.g23;
    spec.model = RODKIT_TUBE_MODEL_THICK;
    spec.rel_tol = 1e-10;
    Tube tube;
    check(rodkit_tube_new(&spec, &tube.p), "rodkit_tube_new");
    std::array<double, 36> k{};
    check(rodkit_tube_rod_stiffness(tube.p, k.data(), 6, estimate), "rodkit_tube_rod_stiffness");
    return k;
}

// ---------------------------------------------------------------------------
// The FE code's sparse direct solver: left-looking LU with threshold partial
// pivoting on a compressed-column matrix (Gilbert & Peierls 1988; the
// algorithm of CSparse's cs_lu). Natural column order: rodkit numbers its
// unknowns along the rod, so the matrix is nearly banded already. The six
// tip boundary rows carry structural entries on the diagonal that are zero
// for a cantilever: pivoting takes another row there.

struct Csc {
    int64_t n = 0;
    std::vector<int64_t> p, i;
    std::vector<double> x;
};

class SparseLu {
  public:
    explicit SparseLu(int64_t n) : n_(n), pinv_(n), work_(n, 0.0), xi_(2 * n), mark_(n, -1), stack_(n) {}

    // Factor P A = L U; false if A is singular to working precision.
    bool factor(const Csc &a, double tol = 0.1) {
        const int64_t n = n_;
        lp_.assign(n + 1, 0);
        up_.assign(n + 1, 0);
        li_.clear(), lx_.clear(), ui_.clear(), ux_.clear();
        std::fill(pinv_.begin(), pinv_.end(), -1);
        std::fill(mark_.begin(), mark_.end(), -1);
        for (int64_t k = 0; k < n; ++k) {
            lp_[k] = (int64_t)li_.size();
            up_[k] = (int64_t)ui_.size();
            const int64_t top = lower_solve(a, k);  // work = L \ A(:, k)
            int64_t ipiv = -1;
            double amax = -1.0;
            for (int64_t q = top; q < n; ++q) {
                const int64_t i = xi_[q];
                if (pinv_[i] < 0) {
                    const double t = std::fabs(work_[i]);
                    if (t > amax) amax = t, ipiv = i;
                } else {
                    ui_.push_back(pinv_[i]);
                    ux_.push_back(work_[i]);
                }
            }
            if (ipiv < 0 || !(amax > 0.0)) return false;
            if (pinv_[k] < 0 && std::fabs(work_[k]) >= tol * amax) ipiv = k;  // keep the diagonal
            const double pivot = work_[ipiv];
            ui_.push_back(k);
            ux_.push_back(pivot);
            pinv_[ipiv] = k;
            li_.push_back(ipiv);
            lx_.push_back(1.0);
            for (int64_t q = top; q < n; ++q) {
                const int64_t i = xi_[q];
                if (pinv_[i] < 0) {
                    li_.push_back(i);
                    lx_.push_back(work_[i] / pivot);
                }
                work_[i] = 0.0;
            }
        }
        lp_[n] = (int64_t)li_.size();
        up_[n] = (int64_t)ui_.size();
        for (auto &i : li_) i = pinv_[i];  // L's rows in pivot order
        return true;
    }

    // Solve A x = b in place.
    void solve(std::vector<double> &b) {
        std::vector<double> &y = work_;
        for (int64_t i = 0; i < n_; ++i) y[pinv_[i]] = b[i];
        for (int64_t j = 0; j < n_; ++j)  // L y = P b (unit diagonal first)
            for (int64_t q = lp_[j] + 1; q < lp_[j + 1]; ++q) y[li_[q]] -= lx_[q] * y[j];
        for (int64_t j = n_ - 1; j >= 0; --j) {  // U x = y (diagonal last)
            y[j] /= ux_[up_[j + 1] - 1];
            for (int64_t q = up_[j]; q < up_[j + 1] - 1; ++q) y[ui_[q]] -= ux_[q] * y[j];
        }
        for (int64_t i = 0; i < n_; ++i) b[i] = y[i], y[i] = 0.0;
    }

    int64_t factor_nnz() const { return (int64_t)(li_.size() + ui_.size()); }

  private:
    // Sparse triangular solve with L so far: the rows reached from A(:, k)
    // (depth-first, topological order in xi_[top..n)), values in work_.
    int64_t lower_solve(const Csc &a, int64_t k) {
        int64_t top = n_;
        for (int64_t q = a.p[k]; q < a.p[k + 1]; ++q)
            if (mark_[a.i[q]] != k) top = dfs(a.i[q], k, top);
        for (int64_t q = a.p[k]; q < a.p[k + 1]; ++q) work_[a.i[q]] = a.x[q];
        for (int64_t q = top; q < n_; ++q) {
            const int64_t j = xi_[q], col = pinv_[j];
            if (col < 0) continue;  // not yet pivotal: no column of L
            const double xj = work_[j];
            for (int64_t r = lp_[col] + 1; r < lp_[col + 1]; ++r) work_[li_[r]] -= lx_[r] * xj;
        }
        return top;
    }

    // Non-recursive depth-first search from row j in the graph of L.
    int64_t dfs(int64_t j, int64_t k, int64_t top) {
        int64_t head = 0;
        stack_[0] = j;
        while (head >= 0) {
            j = stack_[head];
            const int64_t col = pinv_[j];
            if (mark_[j] != k) {
                mark_[j] = k;
                xi_[n_ + head] = col < 0 ? 0 : lp_[col] + 1;  // next child to visit
            }
            bool done = true;
            const int64_t end = col < 0 ? 0 : lp_[col + 1];
            for (int64_t q = xi_[n_ + head]; q < end; ++q) {
                const int64_t i = li_[q];
                if (mark_[i] == k) continue;
                xi_[n_ + head] = q + 1;
                stack_[++head] = i;
                done = false;
                break;
            }
            if (done) {
                --head;
                xi_[--top] = j;
            }
        }
        return top;
    }

    int64_t n_;
    std::vector<int64_t> lp_, li_, up_, ui_, pinv_;
    std::vector<double> lx_, ux_, work_;
    std::vector<int64_t> xi_, mark_, stack_;
};

// ---------------------------------------------------------------------------
// The FE program's nonlinear solver on R(x, Lambda) = 0.

double norm_inf(const std::vector<double> &v) {
    double m = 0.0;
    for (double e : v) m = std::max(m, std::fabs(e));
    return m;
}

struct NewtonStats {
    int64_t steps = 0, iterations = 0, factorisations = 0, residuals = 0, jacobians = 0, cuts = 0;
    double final_residual = 0.0, final_residual_abs = 0.0;
};

class FeSolver {
  public:
    // dof_scale: the typical size of every unknown (the FE code's own units).
    FeSolver(RodkitRod *rod, std::vector<double> dof_scale) : rod_(rod), scale_(std::move(dof_scale)) {
        check(rodkit_rod_unknowns(rod_, &n_), "rodkit_rod_unknowns");
        // The pattern, once: its values are refreshed every iteration.
        int64_t nnz = 0;
        check(rodkit_rod_jacobian_pattern(rod_, nullptr, nullptr, 0, &nnz), "rodkit_rod_jacobian_pattern");
        jac_.n = n_;
        jac_.p.resize(n_ + 1);
        jac_.i.resize(nnz);
        jac_.x.resize(nnz);
        check(rodkit_rod_jacobian_pattern(rod_, jac_.p.data(), jac_.i.data(), nnz, &nnz),
              "rodkit_rod_jacobian_pattern");
        r_.resize(n_), dl_.resize(n_), row_scale_.resize(n_), dx_.resize(n_);
        lu_ = std::make_unique<SparseLu>(n_);
    }

    int64_t unknowns() const { return n_; }
    int64_t nnz() const { return (int64_t)jac_.i.size(); }
    int64_t lu_nnz() const { return lu_->factor_nnz(); }
    const NewtonStats &stats() const { return stats_; }

    // Newton's method at fixed Lambda from x (overwritten). The convergence
    // test, unit-free: each equation's residual against its own largest term
    // |J_ij| * scale_j (the relative out-of-balance), and the correction in
    // the dof scales:  max_i |R_i| / max_j |J_ij s_j| <= RES_TOL  and the last
    // correction max_j |dx_j| / s_j <= DX_TOL.
    bool newton(std::vector<double> &x, double lambda, int max_iter, int *iters) {
        constexpr double RES_TOL = 1e-12, DX_TOL = 1e-8;
        double last_dx = INFINITY;
        for (int it = 0; it <= max_iter; ++it) {
            evaluate(x, lambda);
            const double res = scaled_residual();
            if (!std::isfinite(res)) return false;
            if (res <= RES_TOL && last_dx <= DX_TOL) {
                stats_.final_residual = res;
                stats_.final_residual_abs = norm_inf(r_);
                *iters = it;
                return true;
            }
            if (it == max_iter) break;
            if (!factor()) return false;
            for (int64_t i = 0; i < n_; ++i) dx_[i] = -r_[i];
            lu_->solve(dx_);
            last_dx = 0.0;
            for (int64_t i = 0; i < n_; ++i) {
                x[i] += dx_[i];
                last_dx = std::max(last_dx, std::fabs(dx_[i]) / scale_[i]);
            }
            ++stats_.iterations;
        }
        return false;
    }

    // Load stepping from (x, lambda0) through the given loads, each reached
    // from the last converged state with a tangent predictor
    // dx/dLambda = -J^-1 dR/dLambda (from the Jacobian at the converged
    // state); an increment whose Newton loop fails is halved (at most 10
    // times), as FE codes cut steps. `at` is called at every requested load.
    template <class F>
    void follow(std::vector<double> &x, double lambda0, const std::vector<double> &loads, F at) {
        double lambda = lambda0;
        std::vector<double> tangent(n_, 0.0), trial(n_);
        bool have_tangent = false;
        for (double target : loads) {
            double inc = target - lambda;
            int cuts = 0;
            while (lambda < target) {
                const double next = std::min(target, lambda + inc);
                for (int64_t i = 0; i < n_; ++i) trial[i] = x[i] + (have_tangent ? (next - lambda) * tangent[i] : 0.0);
                int iters = 0;
                if (!newton(trial, next, 20, &iters)) {
                    if (++cuts > 10) throw std::runtime_error("load stepping: increment cut 10 times at Lambda = " +
                                                              std::to_string(lambda));
                    ++stats_.cuts;
                    inc *= 0.5;
                    continue;
                }
                x = trial;
                lambda = next;
                ++stats_.steps;
                if (g_values) std::printf("  step %2lld: Lambda = %-8.5g Newton iterations %d, residual %.2e\n",
                            (long long)stats_.steps, lambda, iters, stats_.final_residual);
                // The predictor for the next step, from J and dR/dLambda at the
                // converged state (evaluated by the convergence test).
                if (!factor()) throw std::runtime_error("singular Jacobian at a converged state (a limit point?)");
                for (int64_t i = 0; i < n_; ++i) tangent[i] = -dl_[i];
                lu_->solve(tangent);
                have_tangent = true;
            }
            at(lambda);
        }
    }

  private:
    void evaluate(const std::vector<double> &x, double lambda) {
        check(rodkit_rod_residual(rod_, x.data(), n_, lambda, r_.data()), "rodkit_rod_residual");
        check(rodkit_rod_jacobian(rod_, x.data(), n_, lambda, jac_.x.data(), nnz(), dl_.data()),
              "rodkit_rod_jacobian");
        ++stats_.residuals, ++stats_.jacobians;
    }

    double scaled_residual() {
        std::fill(row_scale_.begin(), row_scale_.end(), 0.0);
        for (int64_t c = 0; c < n_; ++c)
            for (int64_t q = jac_.p[c]; q < jac_.p[c + 1]; ++q)
                row_scale_[jac_.i[q]] = std::max(row_scale_[jac_.i[q]], std::fabs(jac_.x[q]) * scale_[c]);
        double m = 0.0;
        for (int64_t i = 0; i < n_; ++i) m = std::max(m, std::fabs(r_[i]) / row_scale_[i]);
        return m;
    }

    bool factor() {
        ++stats_.factorisations;
        return lu_->factor(jac_);
    }

    RodkitRod *rod_;
    std::vector<double> scale_;
    int64_t n_ = 0;
    Csc jac_;
    std::vector<double> r_, dl_, row_scale_, dx_;
    std::unique_ptr<SparseLu> lu_;
    NewtonStats stats_;
};

// ---------------------------------------------------------------------------
// Tip of a state: position and rotation vector (rodkit's accessors, not
// offsets into the state).
struct Tip {
    double r[3], rot[3];
};

Tip tip_of(RodkitRod *rod, const std::vector<double> &x, int64_t tip_node) {
    Tip t{};
    check(rodkit_rod_node_state(rod, x.data(), (int64_t)x.size(), tip_node, t.r, nullptr, nullptr, nullptr),
          "rodkit_rod_node_state");
    check(rodkit_rod_node_rotation(rod, x.data(), (int64_t)x.size(), tip_node, t.rot), "rodkit_rod_node_rotation");
    return t;
}

// Linear beam theory for the cantilever with the section law of a
// hemitropic rod (physics.md 2.2): in the bending plane (u2, v1) <-> (m2, n1)
// the law is [[K_b, c2], [c2, G]] (c2 the bend-shear coupling K14 = K25).
// Under a small tip force P e1 the moment is m2 = P (L - s), the shear force
// n1 = P; with D = K_b G - c2^2:
//   u2 = G P (L - s) / D,  v1 = K_b P / D,  u1 = -c2 P / D,  v2 = -c2 P (L - s) / D,
// and integrating x' = v1 + theta2, theta' = u, y' = v2 - theta1 gives
//   x(L) = P L^3 G / (3 D) + P L K_b / D      (Timoshenko with coupling;
//                                              c2 = 0: P L^3/(3 K_b) + P L/G)
//   theta2(L) = P L^2 G / (2 D),  theta1(L) = -c2 P L / D,  y(L) = 0.
// `shear` is the shear term's share of x(L); `uncoupled` the Timoshenko
// deflection with c2 ignored, to show what the coupling does.
struct Linear {
    double x, rot1, rot2, shear, uncoupled;
};

Linear linear_theory(const std::array<double, 36> &k, double p, double l) {
    const double kb = k[0], g = k[3 + 6 * 3], c2 = k[0 + 6 * 3];
    const double d = kb * g - c2 * c2;
    const double x = p * l * l * l * g / (3 * d) + p * l * kb / d;
    return {x, -c2 * p * l / d, p * l * l * g / (2 * d), p * l * kb / d / x, p * l * l * l / (3 * kb) + p * l / g};
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run(int argc, char **argv) {
    // --values (first) adds every figure as a `name = value` line (the tests read them).
    if (argc > 1 && std::string(argv[1]) == "--values") {
        g_values = true;
        --argc;
        ++argv;
    }
    const int64_t elements = argc > 1 ? std::atoll(argv[1]) : 16;
    const int load_steps = argc > 2 ? std::atoi(argv[2]) : 10;
    if (elements < 1 || load_steps < 1) {
        std::fprintf(stderr, "usage: cpp_fe_beam [--values] [elements >= 1] [load_steps >= 1]\n");
        return 2;
    }
    constexpr double LENGTH = 1000.0, LAMBDA_MAX = 5.0, LAMBDA_LINEAR = 1e-4;
    constexpr double TIP_TOL = 1e-9, LINEAR_TOL = 1e-7;
    const auto t_start = std::chrono::steady_clock::now();

    std::printf("rodkit %s embedded in a C++ FE beam program (own load stepping, Newton, sparse LU)\n",
                RODKIT_VERSION_STRING);

    // 1. Section law from the tube.
    const Wall wall;
    double section_error = 0.0;
    const auto k = section_stiffness(wall, &section_error);
    std::printf("1. section: fibre-reinforced hose, A = %g mm, B = %g mm, cords at 30 deg (mid radius)\n",
                wall.inner, wall.outer);
    if (g_values) std::printf("inner_radius = %.17g\nouter_radius = %.17g\nintrinsic_twist = %.17g\n", wall.inner, wall.outer,
                wall.tau0);
    if (g_values) std::printf("e1 = %.17g\ne2 = %.17g\ne3 = %.17g\nnu12 = %.17g\nnu13 = %.17g\nnu23 = %.17g\n", wall.e1, wall.e2,
                wall.e3, wall.nu12, wall.nu13, wall.nu23);
    if (g_values) std::printf("g12 = %.17g\ng13 = %.17g\ng23 = %.17g\n", wall.g12, wall.g13, wall.g23);
    const char *names[6] = {"u1", "u2", "u3", "v1", "v2", "v3"};
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j)
            if (g_values && k[i + 6 * j] != 0.0) std::printf("K_%s_%s = %.17g\n", names[i], names[j], k[i + 6 * j]);
    if (g_values) std::printf("section_error_estimate = %.3e\n", section_error);
    std::printf("  bending K_b = %.6g N mm^2, shear G = %.6g N, bend-shear c2 = %.6g N mm, twist C = %.6g N mm^2,\n"
                "  stretch S = %.6g N, twist-stretch g = %.6g N mm (chiral: the cords wind one way); under a\n"
                "  transverse load the coupling leaves an effective bending stiffness K_b - c2^2/G = %.6g N mm^2\n",
                k[0], k[21], k[18], k[14], k[35], k[2 + 6 * 5], k[0] - k[18] * k[18] / k[21]);

    // 2. The rod: cantilever, dead tip force Lambda * P_ref e1, with P_ref =
    // EI_eff / L^2: Lambda is the elastica's load parameter P L^2 / EI_eff
    // for the effective bending stiffness of this chiral section under a
    // transverse load, EI_eff = K_b - c2^2 / G (linear_theory()).
    const double ei_eff = k[0] - k[18] * k[18] / k[21];
    const double p_ref = ei_eff / (LENGTH * LENGTH);
    RodkitRodSpec spec;
    check(rodkit_rod_spec_default(&spec), "rodkit_rod_spec_default");
    spec.length = LENGTH;
    spec.supports = RODKIT_ROD_SUPPORTS_CANTILEVER;
    spec.tip_force_frame = RODKIT_LOAD_FRAME_DEAD;
    spec.tip_force_x = p_ref;
    spec.scheme = RODKIT_ROD_SCHEME_GAUSS;
    spec.stages = 4;
    spec.elements = elements;
    Rod rod;
    check(rodkit_rod_new_general(&spec, k.data(), 6, &rod.p), "rodkit_rod_new_general");

    // The FE code's dof scales (physics.md 2.4 "Norms"): positions L,
    // quaternions 1, forces K_b/L^2, moments K_b/L. The state is 13-value
    // blocks (r, q, n_b, m_b) for every node and stage point (rodkit.h,
    // rodkit_rod_node_state); a cantilever has no end-control unknowns.
    int64_t n = 0;
    check(rodkit_rod_unknowns(rod.p, &n), "rodkit_rod_unknowns");
    if (n % 13 != 0) throw std::runtime_error("unexpected state layout: " + std::to_string(n) + " unknowns");
    std::vector<double> scale(n);
    for (int64_t i = 0; i < n; ++i) {
        const int64_t c = i % 13;
        scale[i] = c < 3 ? LENGTH : c < 7 ? 1.0 : c < 10 ? p_ref : p_ref * LENGTH;
    }
    FeSolver fe(rod.p, scale);
    std::printf("2. rod: L = %g mm, Gauss-Legendre 4 stages x %lld elements, %lld unknowns, %lld Jacobian entries\n",
                LENGTH, (long long)elements, (long long)n, (long long)fe.nnz());
    if (g_values) std::printf("length = %.17g\nelements = %lld\nunknowns = %lld\njacobian_nnz = %lld\nload_per_lambda = %.17g\n",
                LENGTH, (long long)elements, (long long)n, (long long)fe.nnz(), p_ref);

    // 3. The FE solve: a small step (the linear check), then uniform steps.
    std::vector<double> x(n);
    check(rodkit_rod_straight_state(rod.p, x.data(), n), "rodkit_rod_straight_state");
    std::vector<double> loads{LAMBDA_LINEAR};
    for (int s = 1; s <= load_steps; ++s) loads.push_back(LAMBDA_MAX * s / load_steps);
    Tip lin_tip{};
    std::printf("3. FE Newton: dead tip force P = Lambda * %.6g N along x, Lambda 0 -> %g\n", p_ref, LAMBDA_MAX);
    const auto t_fe = std::chrono::steady_clock::now();
    fe.follow(x, 0.0, loads, [&](double lambda) {
        if (lambda == LAMBDA_LINEAR) lin_tip = tip_of(rod.p, x, elements);
    });
    const double fe_seconds = seconds_since(t_fe);
    const Tip fe_tip = tip_of(rod.p, x, elements);
    const NewtonStats &st = fe.stats();

    // 4. rodkit's own solver on the same rod, to the same load.
    RodkitContinuationOptions opts;
    check(rodkit_continuation_options_default(&opts), "rodkit_continuation_options_default");
    opts.target_lambda = LAMBDA_MAX;
    opts.residual_tol = 1e-12;
    const auto t_anm = std::chrono::steady_clock::now();
    Branch branch;
    const int32_t cst = check(rodkit_rod_continue(rod.p, nullptr, n, 0.0, &opts, nullptr, nullptr, &branch.p),
                              "rodkit_rod_continue");
    if (cst != RODKIT_STATUS_OK)
        throw std::runtime_error(std::string("rodkit_rod_continue did not reach the load: ") +
                                 rodkit_status_string(cst));
    const double anm_seconds = seconds_since(t_anm);
    RodkitBranchInfo info;
    check(rodkit_branch_summary(branch.p, &info), "rodkit_branch_summary");
    std::vector<double> xa(info.state_length);
    check(rodkit_branch_state(branch.p, info.records - 1, xa.data(), info.state_length), "rodkit_branch_state");
    const Tip anm_tip = tip_of(rod.p, xa, elements);
    double dpos = 0.0, drot = 0.0, dstate = 0.0;
    for (int c = 0; c < 3; ++c) {
        dpos = std::max(dpos, std::fabs(fe_tip.r[c] - anm_tip.r[c]) / LENGTH);
        drot = std::max(drot, std::fabs(fe_tip.rot[c] - anm_tip.rot[c]));
    }
    for (int64_t i = 0; i < n; ++i) dstate = std::max(dstate, std::fabs(x[i] - xa[i]) / scale[i]);
    const double tip_angle = std::sqrt(fe_tip.rot[0] * fe_tip.rot[0] + fe_tip.rot[1] * fe_tip.rot[1] +
                                       fe_tip.rot[2] * fe_tip.rot[2]);

    std::printf("  tip at Lambda = %g (P = %.6g N): x = %.6f mm, y = %.6f mm, z = %.6f mm, rotation %.4f deg\n",
                LAMBDA_MAX, LAMBDA_MAX * p_ref, fe_tip.r[0], fe_tip.r[1], fe_tip.r[2], tip_angle * 180.0 / M_PI);
    std::printf("  its own Newton: %lld load steps, %lld iterations, %lld sparse LU factorisations (%lld entries after\n"
                "  fill), %lld step cuts, final scaled residual %.1e; %.2f s\n",
                (long long)st.steps, (long long)st.iterations, (long long)st.factorisations, (long long)fe.lu_nnz(),
                (long long)st.cuts, st.final_residual, fe_seconds);
    if (g_values) std::printf("lambda_max = %.17g\n", LAMBDA_MAX);
    for (int c = 0; c < 3 && g_values; ++c) std::printf("fe_tip_%c = %.17g\n", "xyz"[c], fe_tip.r[c]);
    for (int c = 0; c < 3 && g_values; ++c) std::printf("fe_tip_rot%d = %.17g\n", c + 1, fe_tip.rot[c]);
    if (g_values) std::printf("newton_steps = %lld\nnewton_iterations = %lld\nfactorisations = %lld\nstep_cuts = %lld\n",
                (long long)st.steps, (long long)st.iterations, (long long)st.factorisations, (long long)st.cuts);
    if (g_values) std::printf("final_residual = %.3e\nfinal_residual_abs = %.3e\nlu_nnz = %lld\nfe_seconds = %.3f\n",
                st.final_residual, st.final_residual_abs, (long long)fe.lu_nnz(), fe_seconds);
    std::printf("4. rodkit_rod_continue (ANM) on the same rod to Lambda = %g: %lld steps, %lld factorisations\n",
                LAMBDA_MAX, (long long)info.steps, (long long)info.factorisations);
    for (int c = 0; c < 3 && g_values; ++c) std::printf("anm_tip_%c = %.17g\n", "xyz"[c], anm_tip.r[c]);
    for (int c = 0; c < 3 && g_values; ++c) std::printf("anm_tip_rot%d = %.17g\n", c + 1, anm_tip.rot[c]);
    if (g_values) std::printf("anm_steps = %lld\nanm_seconds = %.3f\n", (long long)info.steps, anm_seconds);
    if (g_values) std::printf("tip_position_difference = %.3e\ntip_rotation_difference = %.3e\nstate_difference = %.3e\n", dpos,
                drot, dstate);
    if (g_values) std::printf("tip_tolerance = %.1e\n", TIP_TOL);
    const bool agree = dpos <= TIP_TOL && drot <= TIP_TOL;
    std::printf("  FE vs rodkit: tip position %.2e L, rotation %.2e rad (tolerance %.0e): %s\n", dpos, drot,
                TIP_TOL, agree ? "agree" : "DISAGREE");

    // 5. The small step against linear theory.
    const double p_lin = LAMBDA_LINEAR * p_ref;
    const Linear lt = linear_theory(k, p_lin, LENGTH);
    const double err_x = std::fabs(lin_tip.r[0] / lt.x - 1.0);
    const double err_rot = std::max(std::fabs(lin_tip.rot[1] / lt.rot2 - 1.0),
                                    std::fabs(lin_tip.rot[0] - lt.rot1) / std::fabs(lt.rot2));
    const double err_y = std::fabs(lin_tip.r[1]) / lt.x;
    const double linear_error = std::max({err_x, err_rot, err_y});
    std::printf("5. small load Lambda = %g (P = %.6g N) vs linear theory with the section's K_b, G, c2:\n",
                LAMBDA_LINEAR, p_lin);
    if (g_values) std::printf("lambda_linear = %.17g\n", LAMBDA_LINEAR);
    if (g_values) std::printf("fe_linear_tip_x = %.17g\nfe_linear_tip_y = %.17g\n", lin_tip.r[0], lin_tip.r[1]);
    if (g_values) std::printf("fe_linear_rot1 = %.17g\nfe_linear_rot2 = %.17g\n", lin_tip.rot[0], lin_tip.rot[1]);
    if (g_values) std::printf("linear_theory_tip_x = %.17g\nlinear_theory_rot1 = %.17g\nlinear_theory_rot2 = %.17g\n", lt.x,
                lt.rot1, lt.rot2);
    if (g_values) std::printf("linear_relative_error = %.3e\nlinear_tolerance = %.1e\n", linear_error, LINEAR_TOL);
    std::printf("  tip deflection %.10g mm, theory %.10g mm (its shear term %.2e of it; without the bend-shear\n"
                "  coupling it would be %.6g mm); tip rotation about y %.6e rad, theory %.6e; about x (out of\n"
                "  plane, from the coupling) %.6e rad, theory %.6e\n",
                lin_tip.r[0], lt.x, lt.shear, lt.uncoupled, lin_tip.rot[1], lt.rot2, lin_tip.rot[0], lt.rot1);
    if (g_values) std::printf("linear_shear_share = %.3e\n", lt.shear);
    const bool linear_ok = linear_error <= LINEAR_TOL;
    std::printf("  linear check (tolerance %.0e): %s\n", LINEAR_TOL, linear_ok ? "passed" : "FAILED");
    if (g_values) std::printf("total_seconds = %.3f\n", seconds_since(t_start));
    return agree && linear_ok ? 0 : 1;
}

}  // namespace

int main(int argc, char **argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "cpp_fe_beam: %s\n", e.what());
        return 1;
    }
}
