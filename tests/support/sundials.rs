//! Test-only safe wrapper over `sundials-sys` (KINSOL and IDA with the dense
//! direct linear solver), for cross-verification (physics.md §4).
//!
//! Include it from a test file compiled only with the `sundials` feature:
//!
//! ```ignore
//! #![cfg(feature = "sundials")]
//! #[path = "support/sundials.rs"]
//! mod sundials;
//! ```
//!
//! Conventions:
//! - every SUNDIALS object is owned by a small RAII handle and freed on every
//!   path (success, error return, panic in a user closure);
//! - every return flag is checked; a negative flag becomes `Err` naming the
//!   call, the flag's name and its value;
//! - user closures run inside `catch_unwind`: a panic becomes a negative
//!   (unrecoverable) return to SUNDIALS, and the wrapper then returns `Err`
//!   carrying the panic message (no unwinding across the C frames);
//! - non-convergence is an `Err`, never a number: KINSOL's
//!   `KIN_STEP_LT_STPTOL` ("step smaller than the step tolerance", the
//!   function-norm test NOT met) is reported as an error.
//!
//! Builds against SUNDIALS 6.x (Debian 6.4.1) and 7.x: it uses
//! `sundials_sys::comm_no_mpi()` for `SUNContext_Create` and avoids the
//! v6-only error-handler API (so SUNDIALS' own error messages still go to
//! stderr).
#![allow(dead_code)]

use std::ops::{Index, IndexMut};
use std::os::raw::{c_int, c_long, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use sundials_sys as sys;

// ---------------------------------------------------------------------------
// Context and owned handles
// ---------------------------------------------------------------------------

/// A SUNDIALS context (`SUNContext_Create` / `SUNContext_Free`). Not `Send`:
/// a context must not be shared between threads.
pub struct Context {
    raw: sys::SUNContext,
}

impl Context {
    pub fn new() -> Result<Self, String> {
        let mut raw: sys::SUNContext = ptr::null_mut();
        // SAFETY: `raw` is a valid out-pointer; the communicator is the
        // "no MPI" value for the linked SUNDIALS major version.
        let flag = unsafe { sys::SUNContext_Create(sys::comm_no_mpi(), &mut raw) };
        if flag < 0 || raw.is_null() {
            return Err(format!("SUNContext_Create failed (flag {flag})"));
        }
        Ok(Self { raw })
    }

    pub fn as_raw(&self) -> sys::SUNContext {
        self.raw
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: created by SUNContext_Create, freed exactly once; all
            // objects created with it are owned by handles that borrow the
            // context, so they are gone by now.
            unsafe {
                sys::SUNContext_Free(&mut self.raw);
            }
        }
    }
}

/// The SUNDIALS version the bindings were generated for (e.g. "6.4.1").
pub fn sundials_version() -> String {
    let bytes: &[u8] = sys::SUNDIALS_VERSION;
    String::from_utf8_lossy(bytes.split(|&b| b == 0).next().unwrap_or(&[])).into_owned()
}

/// Owned serial N_Vector.
struct NVec(sys::N_Vector);

impl NVec {
    fn new(n: usize, ctx: &Context) -> Result<Self, String> {
        // SAFETY: plain constructor; null is checked.
        let v = unsafe { sys::N_VNew_Serial(n as sys::sunindextype, ctx.as_raw()) };
        if v.is_null() {
            return Err(format!("N_VNew_Serial({n}) returned NULL"));
        }
        Ok(Self(v))
    }

    fn from_slice(data: &[f64], ctx: &Context) -> Result<Self, String> {
        let mut v = Self::new(data.len(), ctx)?;
        v.as_mut_slice().copy_from_slice(data);
        Ok(v)
    }

    fn as_slice(&self) -> &[f64] {
        // SAFETY: a live serial vector owns a contiguous array of its length.
        unsafe { nvec_slice(self.0) }
    }

    fn as_mut_slice(&mut self) -> &mut [f64] {
        // SAFETY: as above, and `&mut self` gives exclusive access.
        unsafe { nvec_slice_mut(self.0) }
    }
}

impl Drop for NVec {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: created by N_VNew_Serial, destroyed once.
            unsafe { sys::N_VDestroy(self.0) };
        }
    }
}

/// Owned dense SUNMatrix.
struct DenseMat(sys::SUNMatrix);

impl DenseMat {
    /// A band matrix (SUNBandMatrix) with upper and lower bandwidths; the
    /// same owner type (SUNMatDestroy frees either kind).
    fn band(n: usize, upper: usize, lower: usize, ctx: &Context) -> Result<Self, String> {
        // SAFETY: plain constructor; null is checked.
        let m = unsafe {
            sys::SUNBandMatrix(
                n as sys::sunindextype,
                upper as sys::sunindextype,
                lower as sys::sunindextype,
                ctx.as_raw(),
            )
        };
        if m.is_null() {
            return Err(format!("SUNBandMatrix({n}, {upper}, {lower}) returned NULL"));
        }
        Ok(Self(m))
    }

    fn new(n: usize, ctx: &Context) -> Result<Self, String> {
        let n = n as sys::sunindextype;
        // SAFETY: plain constructor; null is checked.
        let m = unsafe { sys::SUNDenseMatrix(n, n, ctx.as_raw()) };
        if m.is_null() {
            return Err(format!("SUNDenseMatrix({n}, {n}) returned NULL"));
        }
        Ok(Self(m))
    }
}

impl Drop for DenseMat {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: created by SUNDenseMatrix, destroyed once.
            unsafe { sys::SUNMatDestroy(self.0) };
        }
    }
}

/// Owned dense SUNLinearSolver.
struct LinSol(sys::SUNLinearSolver);

impl LinSol {
    fn band(template: &NVec, mat: &DenseMat, ctx: &Context) -> Result<Self, String> {
        // SAFETY: live vector and band matrix of matching size; null is checked.
        let ls = unsafe { sys::SUNLinSol_Band(template.0, mat.0, ctx.as_raw()) };
        if ls.is_null() {
            return Err("SUNLinSol_Band returned NULL".into());
        }
        Ok(Self(ls))
    }

    fn dense(template: &NVec, mat: &DenseMat, ctx: &Context) -> Result<Self, String> {
        // SAFETY: live vector and matrix of matching size; null is checked.
        let ls = unsafe { sys::SUNLinSol_Dense(template.0, mat.0, ctx.as_raw()) };
        if ls.is_null() {
            return Err("SUNLinSol_Dense returned NULL".into());
        }
        Ok(Self(ls))
    }
}

impl Drop for LinSol {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: created by SUNLinSol_Dense, freed once.
            unsafe { sys::SUNLinSolFree(self.0) };
        }
    }
}

/// Owned KINSOL memory.
struct KinMem(*mut c_void);

impl Drop for KinMem {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: created by KINCreate, freed once (KINFree nulls it).
            unsafe { sys::KINFree(&mut self.0) };
        }
    }
}

/// Owned IDA memory.
struct IdaMem(*mut c_void);

impl Drop for IdaMem {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: created by IDACreate, freed once (IDAFree nulls it).
            unsafe { sys::IDAFree(&mut self.0) };
        }
    }
}

/// # Safety
/// `v` must be a live serial N_Vector not mutated during the borrow.
unsafe fn nvec_slice<'a>(v: sys::N_Vector) -> &'a [f64] {
    // SAFETY: by the caller's contract.
    unsafe {
        let n = sys::N_VGetLength(v) as usize;
        let p = sys::N_VGetArrayPointer(v);
        if n == 0 || p.is_null() {
            &[]
        } else {
            std::slice::from_raw_parts(p, n)
        }
    }
}

/// # Safety
/// `v` must be a live serial N_Vector, not aliased during the borrow.
unsafe fn nvec_slice_mut<'a>(v: sys::N_Vector) -> &'a mut [f64] {
    // SAFETY: by the caller's contract.
    unsafe {
        let n = sys::N_VGetLength(v) as usize;
        let p = sys::N_VGetArrayPointer(v);
        if n == 0 || p.is_null() {
            &mut []
        } else {
            std::slice::from_raw_parts_mut(p, n)
        }
    }
}

// ---------------------------------------------------------------------------
// Dense column-major matrix view (what a Jacobian closure fills in)
// ---------------------------------------------------------------------------

/// Mutable view of a SUNDIALS dense matrix: column-major, entry (i, j) at
/// `data[i + j * nrows]`. Zeroed before it is handed to a Jacobian closure.
pub struct DenseColMajor<'a> {
    data: &'a mut [f64],
    nrows: usize,
    ncols: usize,
}

impl<'a> DenseColMajor<'a> {
    /// View over a caller-owned column-major buffer (`data.len() == nrows * ncols`).
    pub fn new(data: &'a mut [f64], nrows: usize, ncols: usize) -> Self {
        assert_eq!(data.len(), nrows * ncols, "DenseColMajor: buffer size");
        Self { data, nrows, ncols }
    }

    /// # Safety
    /// `m` must be a live dense SUNMatrix, not aliased during `'a`.
    unsafe fn from_raw(m: sys::SUNMatrix) -> Self {
        // SAFETY: by the caller's contract; LData = rows * columns.
        unsafe {
            let nrows = sys::SUNDenseMatrix_Rows(m) as usize;
            let ncols = sys::SUNDenseMatrix_Columns(m) as usize;
            let len = sys::SUNDenseMatrix_LData(m) as usize;
            debug_assert_eq!(len, nrows * ncols);
            let p = sys::SUNDenseMatrix_Data(m);
            let data = if len == 0 || p.is_null() { &mut [] } else { std::slice::from_raw_parts_mut(p, len) };
            Self { data, nrows, ncols }
        }
    }

    pub fn nrows(&self) -> usize {
        self.nrows
    }

    pub fn ncols(&self) -> usize {
        self.ncols
    }

    pub fn get(&self, i: usize, j: usize) -> f64 {
        self[(i, j)]
    }

    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        self[(i, j)] = v;
    }

    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        self[(i, j)] += v;
    }

    pub fn fill(&mut self, v: f64) {
        self.data.fill(v);
    }

    /// Column `j` as a contiguous slice.
    pub fn column_mut(&mut self, j: usize) -> &mut [f64] {
        assert!(j < self.ncols, "DenseColMajor: column {j} out of range");
        &mut self.data[j * self.nrows..(j + 1) * self.nrows]
    }

    /// The whole column-major buffer.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        self.data
    }
}

impl Index<(usize, usize)> for DenseColMajor<'_> {
    type Output = f64;
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        assert!(i < self.nrows && j < self.ncols, "DenseColMajor: ({i}, {j}) out of range");
        &self.data[i + j * self.nrows]
    }
}

impl IndexMut<(usize, usize)> for DenseColMajor<'_> {
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut f64 {
        assert!(i < self.nrows && j < self.ncols, "DenseColMajor: ({i}, {j}) out of range");
        &mut self.data[i + j * self.nrows]
    }
}

// ---------------------------------------------------------------------------
// Flags
// ---------------------------------------------------------------------------

/// Name of a KINSOL return flag (`KINSol`, `KINSet*`, `KINGet*`, `KINInit`).
pub fn kin_flag_name(flag: c_int) -> &'static str {
    match flag {
        sys::KIN_SUCCESS => "KIN_SUCCESS",
        sys::KIN_INITIAL_GUESS_OK => "KIN_INITIAL_GUESS_OK",
        sys::KIN_STEP_LT_STPTOL => "KIN_STEP_LT_STPTOL",
        sys::KIN_WARNING => "KIN_WARNING",
        sys::KIN_MEM_NULL => "KIN_MEM_NULL",
        sys::KIN_ILL_INPUT => "KIN_ILL_INPUT",
        sys::KIN_NO_MALLOC => "KIN_NO_MALLOC",
        sys::KIN_MEM_FAIL => "KIN_MEM_FAIL",
        sys::KIN_LINESEARCH_NONCONV => "KIN_LINESEARCH_NONCONV",
        sys::KIN_MAXITER_REACHED => "KIN_MAXITER_REACHED",
        sys::KIN_MXNEWT_5X_EXCEEDED => "KIN_MXNEWT_5X_EXCEEDED",
        sys::KIN_LINESEARCH_BCFAIL => "KIN_LINESEARCH_BCFAIL",
        sys::KIN_LINSOLV_NO_RECOVERY => "KIN_LINSOLV_NO_RECOVERY",
        sys::KIN_LINIT_FAIL => "KIN_LINIT_FAIL",
        sys::KIN_LSETUP_FAIL => "KIN_LSETUP_FAIL",
        sys::KIN_LSOLVE_FAIL => "KIN_LSOLVE_FAIL",
        sys::KIN_SYSFUNC_FAIL => "KIN_SYSFUNC_FAIL",
        sys::KIN_FIRST_SYSFUNC_ERR => "KIN_FIRST_SYSFUNC_ERR",
        sys::KIN_REPTD_SYSFUNC_ERR => "KIN_REPTD_SYSFUNC_ERR",
        sys::KIN_VECTOROP_ERR => "KIN_VECTOROP_ERR",
        sys::KIN_CONTEXT_ERR => "KIN_CONTEXT_ERR",
        _ => "unknown KIN flag",
    }
}

/// Name of a KINLS (linear-solver interface) return flag. The KINLS_*
/// success constant is generated as `u32` by sundials-sys, so it is matched
/// by value.
pub fn kinls_flag_name(flag: c_int) -> &'static str {
    match flag {
        0 => "KINLS_SUCCESS",
        sys::KINLS_MEM_NULL => "KINLS_MEM_NULL",
        sys::KINLS_LMEM_NULL => "KINLS_LMEM_NULL",
        sys::KINLS_ILL_INPUT => "KINLS_ILL_INPUT",
        sys::KINLS_MEM_FAIL => "KINLS_MEM_FAIL",
        sys::KINLS_PMEM_NULL => "KINLS_PMEM_NULL",
        sys::KINLS_JACFUNC_ERR => "KINLS_JACFUNC_ERR",
        sys::KINLS_SUNMAT_FAIL => "KINLS_SUNMAT_FAIL",
        sys::KINLS_SUNLS_FAIL => "KINLS_SUNLS_FAIL",
        _ => "unknown KINLS flag",
    }
}

/// Name of an IDA return flag (`IDASolve`, `IDACalcIC`, `IDASet*`, ...).
pub fn ida_flag_name(flag: c_int) -> &'static str {
    match flag {
        sys::IDA_SUCCESS => "IDA_SUCCESS",
        sys::IDA_TSTOP_RETURN => "IDA_TSTOP_RETURN",
        sys::IDA_ROOT_RETURN => "IDA_ROOT_RETURN",
        sys::IDA_WARNING => "IDA_WARNING",
        sys::IDA_TOO_MUCH_WORK => "IDA_TOO_MUCH_WORK",
        sys::IDA_TOO_MUCH_ACC => "IDA_TOO_MUCH_ACC",
        sys::IDA_ERR_FAIL => "IDA_ERR_FAIL",
        sys::IDA_CONV_FAIL => "IDA_CONV_FAIL",
        sys::IDA_LINIT_FAIL => "IDA_LINIT_FAIL",
        sys::IDA_LSETUP_FAIL => "IDA_LSETUP_FAIL",
        sys::IDA_LSOLVE_FAIL => "IDA_LSOLVE_FAIL",
        sys::IDA_RES_FAIL => "IDA_RES_FAIL",
        sys::IDA_REP_RES_ERR => "IDA_REP_RES_ERR",
        sys::IDA_RTFUNC_FAIL => "IDA_RTFUNC_FAIL",
        sys::IDA_CONSTR_FAIL => "IDA_CONSTR_FAIL",
        sys::IDA_FIRST_RES_FAIL => "IDA_FIRST_RES_FAIL",
        sys::IDA_LINESEARCH_FAIL => "IDA_LINESEARCH_FAIL",
        sys::IDA_NO_RECOVERY => "IDA_NO_RECOVERY",
        sys::IDA_NLS_INIT_FAIL => "IDA_NLS_INIT_FAIL",
        sys::IDA_NLS_SETUP_FAIL => "IDA_NLS_SETUP_FAIL",
        sys::IDA_NLS_FAIL => "IDA_NLS_FAIL",
        sys::IDA_MEM_NULL => "IDA_MEM_NULL",
        sys::IDA_MEM_FAIL => "IDA_MEM_FAIL",
        sys::IDA_ILL_INPUT => "IDA_ILL_INPUT",
        sys::IDA_NO_MALLOC => "IDA_NO_MALLOC",
        sys::IDA_BAD_EWT => "IDA_BAD_EWT",
        sys::IDA_BAD_K => "IDA_BAD_K",
        sys::IDA_BAD_T => "IDA_BAD_T",
        sys::IDA_BAD_DKY => "IDA_BAD_DKY",
        sys::IDA_VECTOROP_ERR => "IDA_VECTOROP_ERR",
        sys::IDA_CONTEXT_ERR => "IDA_CONTEXT_ERR",
        sys::IDA_UNRECOGNIZED_ERROR => "IDA_UNRECOGNIZED_ERROR",
        _ => "unknown IDA flag",
    }
}

/// Name of an IDALS (linear-solver interface) return flag.
pub fn idals_flag_name(flag: c_int) -> &'static str {
    match flag {
        0 => "IDALS_SUCCESS",
        sys::IDALS_MEM_NULL => "IDALS_MEM_NULL",
        sys::IDALS_LMEM_NULL => "IDALS_LMEM_NULL",
        sys::IDALS_ILL_INPUT => "IDALS_ILL_INPUT",
        sys::IDALS_MEM_FAIL => "IDALS_MEM_FAIL",
        sys::IDALS_PMEM_NULL => "IDALS_PMEM_NULL",
        sys::IDALS_JACFUNC_UNRECVR => "IDALS_JACFUNC_UNRECVR",
        sys::IDALS_JACFUNC_RECVR => "IDALS_JACFUNC_RECVR",
        sys::IDALS_SUNMAT_FAIL => "IDALS_SUNMAT_FAIL",
        sys::IDALS_SUNLS_FAIL => "IDALS_SUNLS_FAIL",
        _ => "unknown IDALS flag",
    }
}

/// `Err` for a negative flag: "`call` failed: NAME (value)".
fn check(flag: c_int, call: &str, name: fn(c_int) -> &'static str) -> Result<c_int, String> {
    if flag < 0 {
        Err(format!("{call} failed: {} ({flag})", name(flag)))
    } else {
        Ok(flag)
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "non-string panic payload".to_owned()
    }
}

/// Runs a user closure; a panic is recorded (first one wins) and becomes the
/// unrecoverable return -1. Once a panic is recorded, closures are not called
/// again.
fn guarded(panic: &mut Option<String>, f: impl FnOnce()) -> c_int {
    if panic.is_some() {
        return -1;
    }
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(()) => 0,
        Err(payload) => {
            *panic = Some(panic_message(&*payload));
            -1
        }
    }
}

fn with_panic(err: String, panic: &Option<String>) -> String {
    match panic {
        Some(msg) => format!("{err}; a user closure panicked: {msg}"),
        None => err,
    }
}

// ---------------------------------------------------------------------------
// KINSOL
// ---------------------------------------------------------------------------

/// KINSOL globalisation strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Full Newton steps (`KIN_NONE`).
    None,
    /// Backtracking line search (`KIN_LINESEARCH`).
    LineSearch,
}

#[derive(Clone, Debug)]
pub struct KinsolOptions {
    pub strategy: Strategy,
    /// Stop when `max_i |f_scale_i F_i(u)| <= func_norm_tol` (`KINSetFuncNormTol`).
    pub func_norm_tol: f64,
    /// `KINSetScaledStepTol`. Reaching it before the function-norm test is
    /// an `Err` (`KIN_STEP_LT_STPTOL`).
    pub scaled_step_tol: f64,
    /// `KINSetNumMaxIters`.
    pub max_iters: i64,
    /// `KINSetMaxSetupCalls`: 1 = exact Newton (Jacobian every iteration);
    /// KINSOL's own default is 10 (modified Newton).
    pub max_setup_calls: i64,
    /// `KINSetMaxNewtonStep` (KINSOL's default when `None`).
    pub max_newton_step: Option<f64>,
    /// Diagonal scalings `u_scale`, `f_scale` of `KINSol` (ones when `None`).
    pub u_scale: Option<Vec<f64>>,
    pub f_scale: Option<Vec<f64>>,
}

impl Default for KinsolOptions {
    fn default() -> Self {
        Self {
            strategy: Strategy::LineSearch,
            func_norm_tol: 1e-12,
            scaled_step_tol: 1e-15,
            max_iters: 200,
            max_setup_calls: 1,
            max_newton_step: None,
            u_scale: None,
            f_scale: None,
        }
    }
}

#[derive(Clone, Debug)]
pub struct KinsolStats {
    /// Success flag of `KINSol` (`KIN_SUCCESS` or `KIN_INITIAL_GUESS_OK`).
    pub flag: c_int,
    pub flag_name: &'static str,
    /// Nonlinear (Newton) iterations, `KINGetNumNonlinSolvIters`.
    pub iterations: i64,
    /// Residual evaluations by KINSOL proper, `KINGetNumFuncEvals`.
    pub residual_evals: i64,
    /// Residual evaluations for difference-quotient Jacobians,
    /// `KINGetNumLinFuncEvals` (0 with an analytic Jacobian).
    pub residual_evals_fd: i64,
    /// Jacobian evaluations (analytic or difference quotient), `KINGetNumJacEvals`.
    pub jacobian_evals: i64,
    /// Line-search backtracks, `KINGetNumBacktrackOps`.
    pub backtracks: i64,
    /// Calls of the residual closure counted by the wrapper (all purposes).
    pub residual_calls: u64,
    /// Scaled Euclidean norm `||f_scale * F(u)||_2` at the returned iterate,
    /// `KINGetFuncNorm` (note: the stopping test uses the max norm).
    pub func_norm: f64,
}

/// Signature of a KINSOL Jacobian closure: fill `J = dF/du` at `u` (the
/// matrix arrives zeroed).
pub type KinJacobian<'a> = dyn FnMut(&[f64], &mut DenseColMajor<'_>) + 'a;

/// Write access to a SUNDIALS band matrix (entries outside the band are
/// rejected by a panic, caught at the callback boundary).
pub struct BandView {
    mat: sys::SUNMatrix,
    upper: isize,
    lower: isize,
}

impl BandView {
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        let d = i as isize - j as isize;
        assert!(d >= -self.upper && d <= self.lower, "entry ({i}, {j}) outside the band");
        // SAFETY: `mat` is the live band matrix KINSOL passed; column j's
        // pointer addresses its diagonal and the band rows around it.
        unsafe {
            let col = sys::SUNBandMatrix_Column(self.mat, j as sys::sunindextype);
            *col.offset(d) = v;
        }
    }
}

/// A KINSOL Jacobian closure for the band solver (the matrix arrives zeroed).
pub type KinBandJacobian<'a> = dyn FnMut(&[f64], &mut BandView) + 'a;

struct KinData<'a, 'j> {
    residual: &'a mut dyn FnMut(&[f64], &mut [f64]),
    jacobian: Option<&'a mut KinJacobian<'j>>,
    band: Option<(&'a mut KinBandJacobian<'j>, isize, isize)>,
    residual_calls: u64,
    panic: Option<String>,
}

unsafe extern "C" fn kin_residual(u: sys::N_Vector, f: sys::N_Vector, user_data: *mut c_void) -> c_int {
    // SAFETY: user_data is the `KinData` that outlives the KINSOL memory;
    // u and f are distinct live serial vectors owned by KINSOL.
    let data = unsafe { &mut *(user_data as *mut KinData<'_, '_>) };
    let (u, f) = unsafe { (nvec_slice(u), nvec_slice_mut(f)) };
    data.residual_calls += 1;
    let residual = &mut *data.residual;
    guarded(&mut data.panic, || residual(u, f))
}

unsafe extern "C" fn kin_jacobian(
    u: sys::N_Vector,
    _fu: sys::N_Vector,
    jac: sys::SUNMatrix,
    user_data: *mut c_void,
    _tmp1: sys::N_Vector,
    _tmp2: sys::N_Vector,
) -> c_int {
    // SAFETY: as in `kin_residual`; `jac` is the dense matrix we attached.
    let data = unsafe { &mut *(user_data as *mut KinData<'_, '_>) };
    let u = unsafe { nvec_slice(u) };
    let mut m = unsafe { DenseColMajor::from_raw(jac) };
    m.fill(0.0);
    let Some(jacobian) = data.jacobian.as_mut() else {
        return -1;
    };
    let jacobian = &mut **jacobian;
    guarded(&mut data.panic, || jacobian(u, &mut m))
}

unsafe extern "C" fn kin_band_jacobian(
    u: sys::N_Vector,
    _fu: sys::N_Vector,
    jac: sys::SUNMatrix,
    user_data: *mut c_void,
    _tmp1: sys::N_Vector,
    _tmp2: sys::N_Vector,
) -> c_int {
    // SAFETY: as in `kin_residual`; `jac` is the band matrix we attached.
    let data = unsafe { &mut *(user_data as *mut KinData<'_, '_>) };
    let u = unsafe { nvec_slice(u) };
    // SAFETY: zero the live band matrix before filling it.
    unsafe { sys::SUNMatZero(jac) };
    let Some((jacobian, upper, lower)) = data.band.as_mut() else {
        return -1;
    };
    let mut view = BandView { mat: jac, upper: *upper, lower: *lower };
    let jacobian = &mut **jacobian;
    guarded(&mut data.panic, || jacobian(u, &mut view))
}

/// Solves `F(x) = 0` with KINSOL (dense direct linear solver).
///
/// `x` holds the initial guess on entry; on return it holds KINSOL's last
/// iterate (the root on `Ok`, the iterate where it stopped on `Err`).
/// Without a `jacobian`, KINSOL's difference-quotient Jacobian is used.
/// `Ok` means KINSOL's function-norm test was met (`KIN_SUCCESS` or
/// `KIN_INITIAL_GUESS_OK`); anything else, including `KIN_STEP_LT_STPTOL`,
/// is `Err`.
pub fn kinsol_solve(
    ctx: &Context,
    x: &mut [f64],
    residual: impl FnMut(&[f64], &mut [f64]),
    jacobian: Option<&mut KinJacobian<'_>>,
    opts: &KinsolOptions,
) -> Result<KinsolStats, String> {
    kinsol_solve_with(ctx, x, residual, jacobian, None, opts)
}

/// As [`kinsol_solve`] with SUNDIALS' band direct solver: `upper`/`lower`
/// bandwidths of the Jacobian and a closure filling it.
#[allow(dead_code)] // used by the benches and some test targets only
pub fn kinsol_solve_band(
    ctx: &Context,
    x: &mut [f64],
    residual: impl FnMut(&[f64], &mut [f64]),
    jacobian: &mut KinBandJacobian<'_>,
    upper: usize,
    lower: usize,
    opts: &KinsolOptions,
) -> Result<KinsolStats, String> {
    kinsol_solve_with(ctx, x, residual, None, Some((jacobian, upper, lower)), opts)
}

fn kinsol_solve_with<'a, 'j>(
    ctx: &Context,
    x: &mut [f64],
    mut residual: impl FnMut(&[f64], &mut [f64]),
    jacobian: Option<&'a mut KinJacobian<'j>>,
    band: Option<(&'a mut KinBandJacobian<'j>, usize, usize)>,
    opts: &KinsolOptions,
) -> Result<KinsolStats, String> {
    let n = x.len();
    if n == 0 {
        return Err("kinsol_solve: empty unknown vector".into());
    }
    let scale = |s: &Option<Vec<f64>>, what: &str| -> Result<Vec<f64>, String> {
        match s {
            None => Ok(vec![1.0; n]),
            Some(v) if v.len() != n => Err(format!("kinsol_solve: {what} has length {} != {n}", v.len())),
            Some(v) if v.iter().any(|&s| !(s > 0.0 && s.is_finite())) => {
                Err(format!("kinsol_solve: {what} must be positive and finite"))
            }
            Some(v) => Ok(v.clone()),
        }
    };
    let u_scale = scale(&opts.u_scale, "u_scale")?;
    let f_scale = scale(&opts.f_scale, "f_scale")?;

    let has_jacobian = jacobian.is_some();
    let band_widths = band.as_ref().map(|(_, u, l)| (*u, *l));
    // Declared before the SUNDIALS objects so it outlives them.
    let mut data = KinData {
        residual: &mut residual,
        jacobian,
        band: band.map(|(j, u, l)| (j, u as isize, l as isize)),
        residual_calls: 0,
        panic: None,
    };

    // Field order = drop order: solver memory first, then the linear solver,
    // the matrix, the vectors.
    struct Work {
        mem: KinMem,
        ls: LinSol,
        mat: DenseMat,
        u: NVec,
        u_scale: NVec,
        f_scale: NVec,
    }
    let u = NVec::from_slice(x, ctx)?;
    let u_scale = NVec::from_slice(&u_scale, ctx)?;
    let f_scale = NVec::from_slice(&f_scale, ctx)?;
    let (mat, ls) = match band_widths {
        Some((upper, lower)) => {
            let mat = DenseMat::band(n, upper, lower, ctx)?;
            let ls = LinSol::band(&u, &mat, ctx)?;
            (mat, ls)
        }
        None => {
            let mat = DenseMat::new(n, ctx)?;
            let ls = LinSol::dense(&u, &mat, ctx)?;
            (mat, ls)
        }
    };
    // SAFETY: plain constructor; null is checked.
    let mem = KinMem(unsafe { sys::KINCreate(ctx.as_raw()) });
    if mem.0.is_null() {
        return Err("KINCreate returned NULL".into());
    }
    let w = Work { mem, ls, mat, u, u_scale, f_scale };

    let m = w.mem.0;
    let strategy = match opts.strategy {
        Strategy::None => sys::KIN_NONE,
        Strategy::LineSearch => sys::KIN_LINESEARCH,
    };
    let user_data = &mut data as *mut KinData<'_, '_> as *mut c_void;
    // SAFETY: `m` is live; the callbacks match KINSOL's prototypes; the
    // user data outlives `w`; all vectors/matrices have length n.
    let flag = unsafe {
        check(sys::KINInit(m, Some(kin_residual), w.u.0), "KINInit", kin_flag_name)?;
        check(sys::KINSetUserData(m, user_data), "KINSetUserData", kin_flag_name)?;
        check(sys::KINSetFuncNormTol(m, opts.func_norm_tol), "KINSetFuncNormTol", kin_flag_name)?;
        check(sys::KINSetScaledStepTol(m, opts.scaled_step_tol), "KINSetScaledStepTol", kin_flag_name)?;
        check(sys::KINSetNumMaxIters(m, opts.max_iters as c_long), "KINSetNumMaxIters", kin_flag_name)?;
        check(sys::KINSetMaxSetupCalls(m, opts.max_setup_calls as c_long), "KINSetMaxSetupCalls", kin_flag_name)?;
        if let Some(step) = opts.max_newton_step {
            check(sys::KINSetMaxNewtonStep(m, step), "KINSetMaxNewtonStep", kin_flag_name)?;
        }
        check(sys::KINSetLinearSolver(m, w.ls.0, w.mat.0), "KINSetLinearSolver", kinls_flag_name)?;
        if has_jacobian {
            check(sys::KINSetJacFn(m, Some(kin_jacobian)), "KINSetJacFn", kinls_flag_name)?;
        }
        if band_widths.is_some() {
            check(sys::KINSetJacFn(m, Some(kin_band_jacobian)), "KINSetJacFn", kinls_flag_name)?;
        }
        sys::KINSol(m, w.u.0, strategy, w.u_scale.0, w.f_scale.0)
    };
    x.copy_from_slice(w.u.as_slice());

    let get =
        |f: unsafe extern "C" fn(*mut c_void, *mut c_long) -> c_int, call: &str, name: fn(c_int) -> &'static str| {
            let mut v: c_long = 0;
            // SAFETY: `m` is live and `v` a valid out-pointer.
            check(unsafe { f(m, &mut v) }, call, name).map(|_| v as i64)
        };
    let stats = (|| -> Result<KinsolStats, String> {
        let mut func_norm = 0.0;
        // SAFETY: `m` is live and `func_norm` a valid out-pointer.
        check(unsafe { sys::KINGetFuncNorm(m, &mut func_norm) }, "KINGetFuncNorm", kin_flag_name)?;
        Ok(KinsolStats {
            flag,
            flag_name: kin_flag_name(flag),
            iterations: get(sys::KINGetNumNonlinSolvIters, "KINGetNumNonlinSolvIters", kin_flag_name)?,
            residual_evals: get(sys::KINGetNumFuncEvals, "KINGetNumFuncEvals", kin_flag_name)?,
            residual_evals_fd: get(sys::KINGetNumLinFuncEvals, "KINGetNumLinFuncEvals", kinls_flag_name)?,
            jacobian_evals: get(sys::KINGetNumJacEvals, "KINGetNumJacEvals", kinls_flag_name)?,
            backtracks: get(sys::KINGetNumBacktrackOps, "KINGetNumBacktrackOps", kin_flag_name)?,
            residual_calls: data.residual_calls,
            func_norm,
        })
    })();

    match flag {
        sys::KIN_SUCCESS | sys::KIN_INITIAL_GUESS_OK => stats,
        _ => {
            let what = match &stats {
                Ok(s) => format!(
                    "KINSol did not converge: {} ({flag}) after {} iterations, ||F||_2 = {:e}",
                    kin_flag_name(flag),
                    s.iterations,
                    s.func_norm
                ),
                Err(_) => format!("KINSol did not converge: {} ({flag})", kin_flag_name(flag)),
            };
            Err(with_panic(what, &data.panic))
        }
    }
}

// ---------------------------------------------------------------------------
// IDA
// ---------------------------------------------------------------------------

/// What `IDACalcIC` is asked to do before integrating.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InitialCondition {
    /// `(y0, yp0)` are used as given (must be consistent).
    AsGiven,
    /// `IDA_YA_YDP_INIT`: given the differential components of `y0`
    /// (`id = 1`), compute the algebraic components of `y0` (`id = 0`) and
    /// the differential components of `yp0`. The algebraic components of
    /// `yp0` are left as given (a semi-explicit residual does not use them).
    ComputeAlgebraicAndDerivatives,
    /// `IDA_Y_INIT`: given `yp0`, compute all of `y0`.
    ComputeY,
}

#[derive(Clone, Debug)]
pub struct IdaOptions {
    /// Scalar relative and absolute tolerances (`IDASStolerances`).
    pub rtol: f64,
    pub atol: f64,
    pub initial_condition: InitialCondition,
    /// `IDASetMaxNumSteps` (per output interval; IDA's default is 500).
    pub max_steps: i64,
    /// `IDASetMaxOrd` (IDA's default 5 when `None`).
    pub max_order: Option<i32>,
    /// `IDASetStopTime(last output time)`: never step (hence never evaluate
    /// the residual) beyond the last output time.
    pub stop_at_last_output: bool,
}

impl Default for IdaOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: 1e-12,
            initial_condition: InitialCondition::AsGiven,
            max_steps: 100_000,
            max_order: None,
            stop_at_last_output: true,
        }
    }
}

#[derive(Clone, Debug)]
pub struct IdaStats {
    /// `IDAGetNumSteps`.
    pub steps: i64,
    /// Residual evaluations by IDA proper, `IDAGetNumResEvals`.
    pub residual_evals: i64,
    /// Residual evaluations for difference-quotient Jacobians,
    /// `IDAGetNumLinResEvals` (0 with an analytic Jacobian).
    pub residual_evals_fd: i64,
    /// `IDAGetNumJacEvals`.
    pub jacobian_evals: i64,
    /// `IDAGetNumNonlinSolvIters`, `IDAGetNumNonlinSolvConvFails`.
    pub nonlin_iters: i64,
    pub nonlin_conv_fails: i64,
    /// `IDAGetNumErrTestFails`.
    pub err_test_fails: i64,
    /// `IDAGetLastOrder`.
    pub last_order: i32,
    /// Calls of the residual closure counted by the wrapper (all purposes,
    /// including `IDACalcIC`).
    pub residual_calls: u64,
}

#[derive(Clone, Debug)]
pub struct IdaSolution {
    /// Initial values actually used (after `IDACalcIC` when requested).
    pub y0: Vec<f64>,
    pub yp0: Vec<f64>,
    /// Times returned by `IDASolve`, one per requested output time.
    pub t: Vec<f64>,
    /// `y` and `y'` at those times.
    pub y: Vec<Vec<f64>>,
    pub yp: Vec<Vec<f64>>,
    pub stats: IdaStats,
}

/// Signature of an IDA Jacobian closure: `(t, c_j, y, y', J)`, fill
/// `J = dF/dy + c_j dF/dy'` (the matrix arrives zeroed).
pub type IdaJacobian<'a> = dyn FnMut(f64, f64, &[f64], &[f64], &mut DenseColMajor<'_>) + 'a;

/// The residual closure behind the C callback: `(t, y, y', F)`.
type IdaResidual<'a> = dyn FnMut(f64, &[f64], &[f64], &mut [f64]) + 'a;

struct IdaData<'a, 'j> {
    residual: &'a mut IdaResidual<'a>,
    jacobian: Option<&'a mut IdaJacobian<'j>>,
    residual_calls: u64,
    panic: Option<String>,
}

unsafe extern "C" fn ida_residual(
    t: f64,
    y: sys::N_Vector,
    yp: sys::N_Vector,
    r: sys::N_Vector,
    user_data: *mut c_void,
) -> c_int {
    // SAFETY: user_data is the `IdaData` that outlives the IDA memory; y, yp,
    // r are distinct live serial vectors owned by IDA.
    let data = unsafe { &mut *(user_data as *mut IdaData<'_, '_>) };
    let (y, yp, r) = unsafe { (nvec_slice(y), nvec_slice(yp), nvec_slice_mut(r)) };
    data.residual_calls += 1;
    let residual = &mut *data.residual;
    guarded(&mut data.panic, || residual(t, y, yp, r))
}

// The signature is IDA's (IDALsJacFn): ten arguments fixed by SUNDIALS.
#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn ida_jacobian(
    t: f64,
    cj: f64,
    y: sys::N_Vector,
    yp: sys::N_Vector,
    _r: sys::N_Vector,
    jac: sys::SUNMatrix,
    user_data: *mut c_void,
    _tmp1: sys::N_Vector,
    _tmp2: sys::N_Vector,
    _tmp3: sys::N_Vector,
) -> c_int {
    // SAFETY: as in `ida_residual`; `jac` is the dense matrix we attached.
    let data = unsafe { &mut *(user_data as *mut IdaData<'_, '_>) };
    let (y, yp) = unsafe { (nvec_slice(y), nvec_slice(yp)) };
    let mut m = unsafe { DenseColMajor::from_raw(jac) };
    m.fill(0.0);
    let Some(jacobian) = data.jacobian.as_mut() else {
        return -1;
    };
    let jacobian = &mut **jacobian;
    guarded(&mut data.panic, || jacobian(t, cj, y, yp, &mut m))
}

/// Integrates the implicit DAE `F(t, y, y') = 0` with IDA (dense direct
/// linear solver) from `t0` and returns `y`, `y'` at each of `t_out`
/// (strictly monotone, all on the same side of `t0`).
///
/// `id[i]` is 1 for a differential and 0 for an algebraic component (passed
/// to `IDASetId`; it is what `IDA_YA_YDP_INIT` needs). Without a `jacobian`,
/// IDA's difference-quotient Jacobian is used.
// The arguments are IDA's own (IDAInit's t0, y0, y'0; IDASetId; the residual and
// Jacobian callbacks; the options; the output times), one each, as the tests pass them.
#[allow(clippy::too_many_arguments)]
pub fn ida_solve(
    ctx: &Context,
    t0: f64,
    y0: &[f64],
    yp0: &[f64],
    id: &[f64],
    mut residual: impl FnMut(f64, &[f64], &[f64], &mut [f64]),
    jacobian: Option<&mut IdaJacobian<'_>>,
    opts: &IdaOptions,
    t_out: &[f64],
) -> Result<IdaSolution, String> {
    let n = y0.len();
    if n == 0 {
        return Err("ida_solve: empty state vector".into());
    }
    if yp0.len() != n || id.len() != n {
        return Err(format!("ida_solve: lengths differ (y0 {n}, yp0 {}, id {})", yp0.len(), id.len()));
    }
    if id.iter().any(|&v| v != 0.0 && v != 1.0) {
        return Err("ida_solve: id entries must be 0 (algebraic) or 1 (differential)".into());
    }
    if t_out.is_empty() {
        return Err("ida_solve: no output times".into());
    }
    let dir = (t_out[0] - t0).signum();
    let monotone = dir != 0.0
        && t_out.iter().all(|t| t.is_finite())
        && std::iter::once(t0)
            .chain(t_out.iter().copied())
            .collect::<Vec<_>>()
            .windows(2)
            .all(|w| (w[1] - w[0]) * dir > 0.0);
    if !monotone {
        return Err("ida_solve: output times must be finite, strictly monotone and away from t0".into());
    }

    let has_jacobian = jacobian.is_some();
    let mut data = IdaData { residual: &mut residual, jacobian, residual_calls: 0, panic: None };

    // Field order = drop order (solver memory first).
    struct Work {
        mem: IdaMem,
        ls: LinSol,
        mat: DenseMat,
        y: NVec,
        yp: NVec,
        id: NVec,
    }
    let y = NVec::from_slice(y0, ctx)?;
    let yp = NVec::from_slice(yp0, ctx)?;
    let idv = NVec::from_slice(id, ctx)?;
    let mat = DenseMat::new(n, ctx)?;
    let ls = LinSol::dense(&y, &mat, ctx)?;
    // SAFETY: plain constructor; null is checked.
    let mem = IdaMem(unsafe { sys::IDACreate(ctx.as_raw()) });
    if mem.0.is_null() {
        return Err("IDACreate returned NULL".into());
    }
    let mut w = Work { mem, ls, mat, y, yp, id: idv };
    let m = w.mem.0;
    let user_data = &mut data as *mut IdaData<'_, '_> as *mut c_void;

    let run = |w: &mut Work| -> Result<IdaSolution, String> {
        // SAFETY: `m` is live; callbacks match IDA's prototypes; the user
        // data outlives `w`; all vectors/matrices have length n.
        unsafe {
            check(sys::IDAInit(m, Some(ida_residual), t0, w.y.0, w.yp.0), "IDAInit", ida_flag_name)?;
            check(sys::IDASetUserData(m, user_data), "IDASetUserData", ida_flag_name)?;
            check(sys::IDASStolerances(m, opts.rtol, opts.atol), "IDASStolerances", ida_flag_name)?;
            check(sys::IDASetMaxNumSteps(m, opts.max_steps as c_long), "IDASetMaxNumSteps", ida_flag_name)?;
            if let Some(q) = opts.max_order {
                check(sys::IDASetMaxOrd(m, q as c_int), "IDASetMaxOrd", ida_flag_name)?;
            }
            check(sys::IDASetId(m, w.id.0), "IDASetId", ida_flag_name)?;
            if opts.stop_at_last_output {
                let t_last = *t_out.last().unwrap();
                check(sys::IDASetStopTime(m, t_last), "IDASetStopTime", ida_flag_name)?;
            }
            check(sys::IDASetLinearSolver(m, w.ls.0, w.mat.0), "IDASetLinearSolver", idals_flag_name)?;
            if has_jacobian {
                check(sys::IDASetJacFn(m, Some(ida_jacobian)), "IDASetJacFn", idals_flag_name)?;
            }
            let icopt = match opts.initial_condition {
                InitialCondition::AsGiven => None,
                InitialCondition::ComputeAlgebraicAndDerivatives => Some(sys::IDA_YA_YDP_INIT),
                InitialCondition::ComputeY => Some(sys::IDA_Y_INIT),
            };
            if let Some(icopt) = icopt {
                check(sys::IDACalcIC(m, icopt, t_out[0]), "IDACalcIC", ida_flag_name)?;
                check(sys::IDAGetConsistentIC(m, w.y.0, w.yp.0), "IDAGetConsistentIC", ida_flag_name)?;
            }
        }
        let y0_used = w.y.as_slice().to_vec();
        let yp0_used = w.yp.as_slice().to_vec();

        let mut t_ret = Vec::with_capacity(t_out.len());
        let mut ys = Vec::with_capacity(t_out.len());
        let mut yps = Vec::with_capacity(t_out.len());
        for &tout in t_out {
            let mut tret = t0;
            // SAFETY: `m` live, `w.y`/`w.yp` live vectors of length n.
            let flag = unsafe { sys::IDASolve(m, tout, &mut tret, w.y.0, w.yp.0, sys::IDA_NORMAL) };
            check(flag, &format!("IDASolve(tout = {tout})"), ida_flag_name)
                .map_err(|e| format!("{e} at t = {tret}"))?;
            t_ret.push(tret);
            ys.push(w.y.as_slice().to_vec());
            yps.push(w.yp.as_slice().to_vec());
        }

        let get = |f: unsafe extern "C" fn(*mut c_void, *mut c_long) -> c_int,
                   call: &str,
                   name: fn(c_int) -> &'static str| {
            let mut v: c_long = 0;
            // SAFETY: `m` is live and `v` a valid out-pointer.
            check(unsafe { f(m, &mut v) }, call, name).map(|_| v as i64)
        };
        let mut last_order: c_int = 0;
        // SAFETY: `m` is live and `last_order` a valid out-pointer.
        check(unsafe { sys::IDAGetLastOrder(m, &mut last_order) }, "IDAGetLastOrder", ida_flag_name)?;
        let stats = IdaStats {
            steps: get(sys::IDAGetNumSteps, "IDAGetNumSteps", ida_flag_name)?,
            residual_evals: get(sys::IDAGetNumResEvals, "IDAGetNumResEvals", ida_flag_name)?,
            residual_evals_fd: get(sys::IDAGetNumLinResEvals, "IDAGetNumLinResEvals", idals_flag_name)?,
            jacobian_evals: get(sys::IDAGetNumJacEvals, "IDAGetNumJacEvals", idals_flag_name)?,
            nonlin_iters: get(sys::IDAGetNumNonlinSolvIters, "IDAGetNumNonlinSolvIters", ida_flag_name)?,
            nonlin_conv_fails: get(sys::IDAGetNumNonlinSolvConvFails, "IDAGetNumNonlinSolvConvFails", ida_flag_name)?,
            err_test_fails: get(sys::IDAGetNumErrTestFails, "IDAGetNumErrTestFails", ida_flag_name)?,
            last_order,
            residual_calls: 0, // filled in below, once `data` is readable again
        };
        Ok(IdaSolution { y0: y0_used, yp0: yp0_used, t: t_ret, y: ys, yp: yps, stats })
    };
    let result = run(&mut w);
    drop(w);
    match result {
        Ok(mut sol) => {
            sol.stats.residual_calls = data.residual_calls;
            Ok(sol)
        }
        Err(e) => Err(with_panic(e, &data.panic)),
    }
}

/// KINSOL (exact Newton: the problem's own sparse Jacobian densified every
/// iteration; tolerances scaled by its equation and unknown scales) on a
/// rodkit `Problem` at fixed Λ from `start`; returns its root, asserting
/// a scaled residual ≤ 3e-11 (1e-11 asked: the stiff rods' rounding floor
/// is ~1e-12, a charged plectoneme's pair sums' ~1e-11 — KINSOL stopped at
/// 1.3e-11 on the 300 bp scene's unstable state at coexistence). The
/// cross-check of tests/sundials_rod.rs, tests/sundials_charged.rs and
/// tests/supercoil_energy.rs.
pub fn kinsol_problem_root<P: rodkit::continuation::Problem + ?Sized>(
    ctx: &Context,
    sys: &mut P,
    lambda: f64,
    start: &[f64],
) -> Vec<f64> {
    let n = sys.dim();
    let eq = sys.equation_scales();
    let (us, _) = sys.unknown_scales();
    let pattern = sys.pattern().clone();
    let sys = std::cell::RefCell::new(sys);
    let mut x = start.to_vec();
    let residual = |u: &[f64], f: &mut [f64]| sys.borrow_mut().residual(u, lambda, f);
    let mut vals = vec![0.0; pattern.nnz()];
    let mut dl = vec![0.0; n];
    let mut jac = |u: &[f64], m: &mut DenseColMajor<'_>| {
        sys.borrow_mut().jacobian(u, lambda, &mut vals, &mut dl);
        m.fill(0.0);
        for j in 0..n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                m.set(pattern.row_idx[k], j, vals[k]);
            }
        }
    };
    let opts = KinsolOptions {
        // Scaled max norm 1e-11: the rounding floor of the stiff rods here
        // (EA = 2.6e4 K_b/L²) is ~1e-12.
        func_norm_tol: 1e-11,
        scaled_step_tol: 1e-16,
        max_setup_calls: 1,
        u_scale: Some(us.iter().map(|s| 1.0 / s).collect()),
        f_scale: Some(eq.iter().map(|s| 1.0 / s).collect()),
        ..Default::default()
    };
    let stats = kinsol_solve(ctx, &mut x, residual, Some(&mut jac), &opts).expect("KINSOL converges");
    assert!(stats.func_norm <= 3e-11, "KINSOL stopped at {:e}", stats.func_norm);
    x
}
