//! Bifurcation points on a branch: detection, location, branch switching
//! (physics.md §2.4).
//!
//! Detection uses two indicators of the bordered tangent B (regular at
//! folds, singular at bifurcations): a sign change of det B (a simple
//! bifurcation) and a local minimum of its smallest singular value σ_min
//! (any bifurcation, including the double ones of rods with rotational
//! symmetry, where two eigenvalues cross together and no determinant
//! changes sign). Location minimises σ_min along the branch between the
//! neighbouring records by golden-section search on the arc length (σ_min
//! has a V-shaped zero there), each trial point Newton-corrected on the
//! branch. A candidate whose minimum is not small (relative to σ_min at the
//! ends of the bracket) is not a bifurcation and is dropped.
//!
//! At the located point, the right singular vectors of B for the small
//! singular values span its null space: the tangents of the bifurcating
//! branches (orthogonal to the branch's own tangent in ⟨·,·⟩_W, by the
//! border row). [`branch_start`] turns one into a [`Resume`] from which
//! either engine follows the new branch.

use super::corrector::{correct, Plane, Reuse};
use super::run::{Context, Factors};
use super::{Problem, Resume, Scaling};
use crate::error::Result;
use crate::linalg::dense::sub;

/// A located bifurcation point.
#[derive(Clone, Debug, PartialEq)]
pub struct Bifurcation {
    pub lambda: f64,
    pub x: Vec<f64>,
    /// Unit tangent of the branch it was found on (in ⟨·,·⟩_W).
    pub tangent_x: Vec<f64>,
    pub tangent_lambda: f64,
    /// The three smallest singular values of B at the point, ascending.
    pub singular_values: Vec<f64>,
    /// Number of (near-)zero singular values: 1 for a simple bifurcation,
    /// 2 for a double one (rotational symmetry).
    pub multiplicity: usize,
    /// Null directions (x part, Λ part), one per zero singular value,
    /// normalised in ⟨·,·⟩_W.
    pub null_vectors: Vec<(Vec<f64>, f64)>,
    /// Whether det B changed sign across it.
    pub det_sign_change: bool,
    /// Whether the signed σ_min (the records' test function) changed sign
    /// across its bracket (false: found as a dip of |σ_min|).
    pub test_function_change: bool,
    /// The branch record it follows: it lies between records `record` and
    /// `record + 1` (set by the run; resumed branches renumber it).
    pub record: usize,
    /// σ_min at the bracket's ends (the scale the minimum is judged against).
    pub bracket_sigma: f64,
}

/// A bracket of records where a monitored function said a bifurcation
/// must lie, but none was located: the branch reports it instead of
/// dropping it (a status, not an OK and a silent miss).
#[derive(Clone, Debug, PartialEq)]
pub struct Unresolved {
    /// The bracket's records (first, last).
    pub records: (usize, usize),
    /// Λ at the bracket's ends.
    pub lambdas: (f64, f64),
    /// What asked for a location: det B changed sign over the bracket, the
    /// signed σ_min did.
    pub det_sign_change: bool,
    pub test_function_change: bool,
    /// Why no point was located.
    pub reason: String,
}

/// What a bracket's records said.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Evidence {
    pub det_sign_change: bool,
    pub test_function_change: bool,
}

/// Where the ANM's series indicator ([`super::indicator`]) puts a
/// bifurcation inside a step: the roots of μ(a) on (0, step], and the
/// step's series X_p (n + 1 each, Λ last) — the predictor of the
/// location's trial points.
#[derive(Clone, Debug)]
pub(crate) struct SeriesHint {
    /// The record the step starts at.
    pub record: usize,
    pub roots: Vec<f64>,
    pub step: f64,
    /// The series (empty without roots: no predictor needed).
    pub series: Vec<Vec<f64>>,
    /// μ has no root on the whole step, certainly
    /// ([`super::indicator::Indicator::clear_of_roots`]).
    pub clear: bool,
}

impl SeriesHint {
    /// X(a) = Σ a^p X_p: the state and Λ.
    fn evaluate(&self, a: f64) -> (Vec<f64>, f64) {
        let n = self.series[0].len() - 1;
        let mut x = vec![0.0; n + 1];
        for c in self.series.iter().rev() {
            for (xi, ci) in x.iter_mut().zip(c) {
                *xi = *xi * a + ci;
            }
        }
        let l = x.pop().unwrap_or(0.0);
        (x, l)
    }
}

/// A point of the branch with its tangent.
#[derive(Clone, Debug)]
pub(crate) struct State {
    pub x: Vec<f64>,
    pub lambda: f64,
    pub tx: Vec<f64>,
    pub tl: f64,
}

/// Locate a bifurcation between `left` and `right` (states on the branch,
/// `left` before `right`) to `tol` in scaled arc length: the point and its
/// arc parameter along `left`'s tangent. Returns None when the minimum of
/// σ_min is not small enough to be a singular point.
/// `tols`: the residual tolerance of the trial points and the location's.
pub(crate) fn locate<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    left: &State,
    right: &State,
    evidence: Evidence,
    (residual_tol, tol): (f64, f64),
    hint: Option<&SeriesHint>,
) -> Result<Option<(Bifurcation, f64)>> {
    let dx = sub(&right.x, &left.x);
    let span = ctx.scaling.dot(&dx, right.lambda - left.lambda, &left.tx, left.tl);
    // The point at arc parameter τ on the hyperplane ⟨X − X_L − τ t_L, t_L⟩ = 0,
    // predicted on the tangent — or on the ANM step's series, which lies on
    // that hyperplane (its a is this τ) and on the branch to its ε.
    let mut point = |tau: f64, ctx: &mut Context| -> Result<(Vec<f64>, f64, f64)> {
        let anchor: Vec<f64> = left.x.iter().zip(&left.tx).map(|(a, t)| a + tau * t).collect();
        let l_anchor = left.lambda + tau * left.tl;
        let (mut x, mut l) = match hint.filter(|h| tau <= h.step && !h.series.is_empty()) {
            Some(h) => h.evaluate(tau),
            None => (anchor.clone(), l_anchor),
        };
        let plane = Plane::new((&anchor, l_anchor), (&left.tx, left.tl));
        correct(problem, ctx, &mut x, &mut l, plane, residual_tol, Reuse::No)?;
        ctx.factorise(problem, &x, l, (&left.tx, left.tl), Factors::ForSolves)?;
        // The trials lie in one bracket: σ_min's directions there are the
        // last trial's (or the bracket end's), so the monitor starts from
        // them — two iterations instead of three to six from a fixed start.
        let sigma = ctx.bordered.signed_smallest_singular_value(true, &mut ctx.counts);
        Ok((x, l, sigma))
    };
    // A root of the series indicator: first the short bracket around it
    // (1e-3 of the step, at least 100 tol: the series' accuracy), then one
    // ten times wider (a root the truncated μ(a) moved); where σ_min does
    // not change sign across either, the whole bracket.
    let mut narrowed = None;
    if let Some(r) = hint.and_then(|h| h.roots.first()) {
        for width in [1e-3, 1e-2] {
            let w = (width * span.abs()).max(100.0 * tol);
            let (lo, hi) = ((r - w).max(0.0), (r + w).min(span));
            if lo >= hi {
                break;
            }
            let (slo, shi) = (point(lo, ctx)?.2, point(hi, ctx)?.2);
            if slo * shi < 0.0 {
                narrowed = Some((lo, hi, slo, shi));
                ctx.counts.series_located += 1;
                break;
            }
        }
    }
    let (a0, b0, sa, sb) = match narrowed {
        Some(n) => n,
        None => (0.0, span, point(0.0, ctx)?.2, point(span, ctx)?.2),
    };
    let span = b0 - a0;
    let ends = sa.abs().max(sb.abs());
    let (mut a, mut b) = (a0, b0);
    // A trial point that did not converge: if nothing singular is found
    // without it, the location failed (an error), not "no bifurcation".
    let mut failed = None;
    // The last trial point, when it was taken where asked: (τ, x, Λ, σ).
    let mut held: Option<(f64, Vec<f64>, f64, f64)> = None;
    if sa * sb < 0.0 {
        // A sign change of the signed σ_min (simple points): it crosses
        // zero linearly, so regula falsi (Illinois) converges
        // superlinearly — a handful of trial points instead of golden
        // section's ~45 at tol 1e-10.
        let (mut fa, mut fb) = (sa, sb);
        // The opposite end's own σ (Illinois halves fa, not this).
        let mut ra = sa;
        let mut best = if sa.abs() < sb.abs() { a0 } else { b0 };
        let mut best_f = sa.abs().min(sb.abs());
        let mut last = f64::NAN;
        for trial in 0..60 {
            // Without det B's evidence the sign change may be the singular
            // vectors turning orthogonal (a jump, not a zero: a twisted
            // rod's pair of modes every 2π): regula falsi gains nothing on a
            // jump, so four trials that leave |σ_min| at the ends' scale end
            // the search (a zero, crossed linearly, is near after one or two).
            if trial == 4 && !evidence.det_sign_change && best_f > 0.2 * sa.abs().min(sb.abs()) {
                return Ok(None);
            }
            let c = b - fb * (b - a) / (fb - fa);
            // Strictly inside the bracket (1 % margins), so it shrinks.
            let (lo, hi) = (a.min(b), a.max(b));
            let c = c.clamp(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo));
            // Right at the singular point the corrector itself may fail to
            // converge (its matrix is singular there): the best point so
            // far is then as close as the location gets.
            // Exactly on the singular point (the series indicator's
            // predictor can put a trial there to the last bit) the factors
            // do not exist: half the tolerance beside it is as close.
            // Whatever this trial leaves in the factorisation, it is not
            // an earlier trial's.
            held = None;
            let fc = match point(c, ctx) {
                Ok((x, l, fc)) => {
                    held = Some((c, x, l, fc));
                    fc
                }
                Err(_) => match point(c + 0.5 * tol, ctx).or_else(|_| point(c - 0.5 * tol, ctx)) {
                    Ok((_, _, fc)) => fc,
                    Err(e) => {
                        failed = Some(e);
                        break;
                    }
                },
            };
            if fc.abs() < best_f {
                (best, best_f) = (c, fc.abs());
            }
            // σ's slope at c, no steeper than either secant to it — from
            // the far end (its own σ: Illinois halves fa, not ra) and from
            // the last trial — so that a crossing flatter than linear (the
            // secants then differ) does not pass for a near one.
            let secant = |t: f64, f: f64| (f - fc).abs() / (t - c).abs().max(f64::MIN_POSITIVE);
            let slope = secant(a, ra).min(secant(b, fb));
            if fc * fb < 0.0 {
                (a, fa, ra) = (b, fb, fb);
            } else {
                fa *= 0.5; // Illinois: the end kept twice counts half
            }
            (b, fb) = (c, fc);
            let moved = (c - last).abs();
            last = c;
            // σ crosses zero linearly at a simple point: c lies within
            // (|σ(c)| + floor)/slope of the zero, the floor being the
            // round-off of a σ computed there (BorderedLu::singular_floor).
            // Once that is within half the tolerance the location is done —
            // further trials would only shrink the bracket by its 1 %
            // margins, a hundredfold each, on signs read at the round-off.
            let near = fc.abs() + ctx.bordered.singular_floor() <= 0.5 * tol * slope;
            if fc == 0.0 || (a - b).abs() <= tol || moved <= 0.5 * tol || near {
                break;
            }
        }
        (a, b) = (best, best);
    } else {
        // Golden-section search for the minimum of |σ_min|(τ) on [0, span]
        // (a double point: σ_min touches zero without changing sign). At most
        // 120 reductions (0.618^120 ≈ 1e-25 of the span): a tolerance below
        // the arc length's rounding would otherwise never be met.
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
        let (mut fc, mut fd) = (point(c, ctx)?.2.abs(), point(d, ctx)?.2.abs());
        let mut reductions = 0;
        while (b - a).abs() > tol && reductions < 120 {
            reductions += 1;
            if fc < fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = point(c, ctx)?.2.abs();
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = point(d, ctx)?.2.abs();
            }
        }
    }
    let tau = 0.5 * (a + b);
    // The last trial when it is the point (its factors are the ones held),
    // else the point again. Exactly on the singular point: half the
    // tolerance beside it (as above).
    let (x, lambda, at_point) = match held.filter(|h| h.0 == tau) {
        Some((_, x, l, s)) => (x, l, s),
        None => match point(tau, ctx) {
            Ok(p) => p,
            Err(e) => match point(tau + 0.5 * tol, ctx).or_else(|_| point(tau - 0.5 * tol, ctx)) {
                Ok(p) => p,
                Err(_) => return Err(e),
            },
        },
    };
    // Singular to working precision (σ_1 below ε‖Ã‖_F: a location that
    // converged onto the zero to the last bit), the other values and
    // vectors cannot be resolved there (BorderedLu::singular_floor): they
    // are taken beside the point, at the least of a series of steps (each
    // ten times the last, at most half the tolerance) that lifts σ_1 above
    // the floor, and differ from the point's by that step's share of their
    // slope. The point and its σ_1 stay the located ones. The lean monitor
    // (Options::lean_monitor) takes the monitor's word for σ_1 at the
    // point, and starts where σ_1, linear off the zero at about the
    // bracket's slope, is 16 floors (at least 1e-3 of the tolerance); the
    // classic one finds σ_1 by the point's own vectors and starts at 1e-3.
    let floor = ctx.bordered.singular_floor();
    let lean = ctx.bordered.lean_monitor();
    let skip = lean && at_point.abs() < floor;
    let (mut sigma, mut vectors) = if skip {
        (vec![at_point.abs(); 3], vec![])
    } else {
        // From the located point's own monitor vectors (the third column fixed).
        ctx.bordered.smallest_singular_vectors(3, &mut ctx.counts)
    };
    if sigma[0] < floor {
        let mut step = match lean {
            true => (16.0 * floor * span.abs() / ends.max(1e-300)).clamp(1e-3 * tol, 0.5 * tol),
            false => 1e-3 * tol,
        };
        let mut found = false;
        'beside: loop {
            for side in [step, -step] {
                if point(tau + side, ctx).is_ok() {
                    let (s, v) = ctx.bordered.smallest_singular_vectors(3, &mut ctx.counts);
                    if s[0] >= ctx.bordered.singular_floor() {
                        sigma.splice(1.., s[1..].iter().copied());
                        vectors = v;
                        found = true;
                        break 'beside;
                    }
                }
            }
            if step >= 0.5 * tol {
                break;
            }
            step = (10.0 * step).min(0.5 * tol);
        }
        if skip && !found {
            // Nowhere resolved: the point's own, as the classic monitor has.
            point(tau, ctx)?;
            (sigma, vectors) = ctx.bordered.smallest_singular_vectors(3, &mut ctx.counts);
        }
    }
    // The bracket was resolved to `tol`: a genuine zero leaves σ_min at
    // O(tol) of the end values; a mere dip (no singularity) stays at their scale.
    // (Clamped: a bracket shorter than the tolerance would make any σ "small".)
    let small = (100.0 * tol / span.abs()).clamp(1e-6, 1e-2) * ends;
    let multiplicity = sigma.iter().take(2).filter(|&&s| s <= small).count();
    if multiplicity == 0 {
        return match failed {
            Some(e) => Err(e),
            // σ_min turned sign and fell three orders below the bracket's
            // ends without reaching zero: a singular point missed by a
            // little (a symmetry the discretisation breaks splits a double
            // point off the branch — a mesh not symmetric about the rod's
            // middle under a twist — or an imperfection), not the mode
            // pair's turn (which stays at the ends' scale). Reported, never
            // dropped.
            None if evidence.test_function_change && sigma[0] < 1e-3 * ends => Err(crate::error::Error::new(
                crate::status::Status::ErrNotConverged,
                format!(
                    "σ_min changed sign and fell to {:.1e} of its value at the bracket's ends (at Λ = {lambda}) \
                     without reaching zero: a near-singular point, not a located bifurcation",
                    sigma[0] / ends
                ),
            )),
            None => Ok(None),
        };
    }
    let n = x.len();
    let null_vectors = vectors
        .iter()
        .take(multiplicity)
        .map(|v| {
            let norm = ctx.scaling.norm(&v[..n], v[n]);
            (v[..n].iter().map(|a| a / norm).collect(), v[n] / norm)
        })
        .collect();
    let bif = Bifurcation {
        lambda,
        x,
        tangent_x: left.tx.clone(),
        tangent_lambda: left.tl,
        singular_values: sigma,
        multiplicity,
        null_vectors,
        det_sign_change: evidence.det_sign_change,
        test_function_change: evidence.test_function_change,
        record: 0,
        bracket_sigma: ends,
    };
    Ok(Some((bif, tau)))
}

/// A second simple bifurcation in the bracket (`left`, `right`) beside the
/// one located at arc parameter `tau` (along `left`'s tangent), called for
/// by det B's signs (`left_sign` at `left`): det B is taken on either side
/// of the located point, δ = 1e-3 of the bracket (at least 10 tol) away,
/// and the piece whose ends' signs differ is searched. None if neither
/// piece changes sign or its minimum of σ_min is not a zero (the arc
/// parameter returned is along the searched piece's first tangent).
pub(crate) fn locate_beside<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    (left, right): (&State, &State),
    tau: f64,
    left_sign: f64,
    tols: (f64, f64),
) -> Result<Option<(Bifurcation, f64)>> {
    let span = ctx.scaling.dot(&sub(&right.x, &left.x), right.lambda - left.lambda, &left.tx, left.tl);
    let delta = (1e-3 * span.abs()).max(10.0 * tols.1);
    let evidence = Evidence { det_sign_change: true, test_function_change: false };
    let mut found = None;
    if tau - delta > 0.0 {
        let (before, sign) = signed_state(problem, ctx, left, tau - delta, tols.0)?;
        if sign * left_sign < 0.0 {
            found = locate(problem, ctx, left, &before, evidence, tols, None)?;
        }
    }
    if found.is_none() && tau + delta < span {
        let (after, sign) = signed_state(problem, ctx, left, tau + delta, tols.0)?;
        let right_sign = {
            let (_, s) = signed_state(problem, ctx, left, span, tols.0)?;
            s
        };
        if sign * right_sign < 0.0 {
            found = locate(problem, ctx, &after, right, evidence, tols, None)?;
        }
    }
    // Not the first point again (a search that slid back to it).
    let at = |b: &Bifurcation| ctx.scaling.dot(&sub(&b.x, &left.x), b.lambda - left.lambda, &left.tx, left.tl);
    Ok(found.filter(|(b, _)| (at(b) - tau).abs() > 0.5 * delta))
}

/// The branch point at arc parameter `tau` along `from`'s tangent (on the
/// hyperplane through from + τ t), its tangent and sign det B (simplicial
/// factors: the sign is exact).
fn signed_state<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    from: &State,
    tau: f64,
    residual_tol: f64,
) -> Result<(State, f64)> {
    let mut x: Vec<f64> = from.x.iter().zip(&from.tx).map(|(a, t)| a + tau * t).collect();
    let mut l = from.lambda + tau * from.tl;
    let (anchor, l0) = (x.clone(), l);
    correct(problem, ctx, &mut x, &mut l, Plane::new((&anchor, l0), (&from.tx, from.tl)), residual_tol, Reuse::No)?;
    ctx.factorise(problem, &x, l, (&from.tx, from.tl), Factors::Exact)?;
    let (tx, tl) = ctx.tangent()?;
    let (sign, _) = ctx.bordered.determinant_signs(&ctx.scaling, &tx, tl);
    Ok((State { x, lambda: l, tx, tl }, sign))
}

/// A start on the branch leaving `bif` along `direction` (x part, Λ part;
/// e.g. one of `bif.null_vectors`, or a combination for a double point),
/// with first step `step`. The direction is made W-orthogonal to the old
/// branch's tangent and normalised.
pub fn branch_start(bif: &Bifurcation, direction: (&[f64], f64), step: f64, scaling: &Scaling) -> Resume {
    let c = scaling.dot(direction.0, direction.1, &bif.tangent_x, bif.tangent_lambda);
    let mut tx: Vec<f64> = direction.0.iter().zip(&bif.tangent_x).map(|(d, t)| d - c * t).collect();
    let mut tl = direction.1 - c * bif.tangent_lambda;
    let norm = scaling.norm(&tx, tl);
    tx.iter_mut().for_each(|v| *v /= norm);
    tl /= norm;
    Resume {
        x: bif.x.clone(),
        lambda: bif.lambda,
        tangent_x: tx,
        tangent_lambda: tl,
        step,
        previous: None,
        modes: None,
    }
}
