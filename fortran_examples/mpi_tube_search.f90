! Tube material search over MPI ranks (issue 21; physics.md 1.5; the serial
! Rust search is benches/tube_search.rs): does torsion-free (T = 0),
! pressure-free, open-ended stretching of a thick tube, lambda from 1 to 1.5
! (or until the solver stops),
!   (a) overwind first, then unwind: a maximum of s*psi(lambda), s the
!       reference sense, or
!   (b) deflate first, then inflate: a minimum of the outer radius b(lambda)?
!
! Usage:  mpirun -np P f_mpi_tube_search [--samples N] [--seed S]
!                [--chunk K] OUTDIR
!         (defaults N = 256, S = 1, K = 8; OUTDIR is created if missing,
!         its parent must exist)
! Output: OUTDIR/samples.csv (every sample, in sample order: class,
!         parameters, coarse findings, confirmation), OUTDIR/hits.csv (the
!         confirmed hits only, same columns), OUTDIR/checkpoints/ (one file
!         per finished chunk) and a short report on standard output (rank 0).
!
! SAMPLING. Sample i (0-based) has class mod(i, 4) (svk_thick, svk_thick_inc,
! hgo_fixed, hgo_helix) and parameters drawn from its own block of a MINSTD
! stream (x <- 48271 x mod (2^31 - 1), in int64: products stay below 2^47):
! the block starts at x = 48271^(256 i) x0 mod (2^31 - 1), x0 = 1 + mod(seed,
! 2^31 - 2), reached by square-and-multiply (products below 2^62), and holds
! 256 draws. Parameters are therefore a pure function of (seed, i): any rank
! reproduces any sample, whatever the number of ranks. Ranges (lengths in
! units of the outer radius B = 1, moduli in units of E1 = 1 (SVK) or of the
! matrix shear modulus mu = 1 (fibre walls); those of benches/tube_search.rs):
!   svk_thick      thick compressible orthotropic Saint Venant-Kirchhoff,
!                  reinforcement (axis 1) on the helix alpha(R) = atan(tau0 R):
!                  A log-uniform in [0.02, 0.7], tau0 uniform in [0.5, 6],
!                  E2, E3 log-uniform in [0.01, 10], nu12 uniform in
!                  [-0.8, 1.2], nu13, nu23 uniform in [-0.5, 0.9], G12, G13,
!                  G23 log-uniform in [0.003, 3]; the constants are redrawn
!                  (at most 100 times, from the same block) until
!                  rodkit_tube_new accepts them as positive definite
!   svk_thick_inc  the same, incompressible (J = 1)
!   hgo_fixed      neo-Hookean matrix (incompressible with probability 0.4,
!                  else Lame lambda log-uniform in [0.3, 300]) plus two fibre
!                  families of opposite hand at fixed angles +beta1, -beta2,
!                  beta uniform in [1, 88] degrees, k1 log-uniform in
!                  [0.05, 500], k2 log-uniform in [0.01, 30] per family;
!                  A uniform in [0.3, 0.95], tau0 = 0
!   hgo_helix      the same matrix, two families on the helix atan(tau0 R)
!                  with hands +1 and -1, tau0 uniform in [0.3, 6], A
!                  log-uniform in [0.05, 0.9]
!
! SPLIT. Samples are grouped in chunks of K consecutive samples. The chunks
! are dealt dynamically: every rank, rank 0 included, takes the next chunk
! from a counter held by rank 0 (an MPI window; MPI_Fetch_and_op under a
! shared passive-target lock) until none is left, so a rank that drew
! cheap samples (sweeps that stop early, no hit to confirm) takes more
! chunks and one that drew costly ones fewer (a chunk's cost varies ~4x).
! Which rank computes a chunk changes from run to run; what it computes
! does not (sample i is a function of (seed, i)), and rank 0 puts the
! gathered records in sample order. A restarted run takes the finished
! chunks from the checkpoints, whatever P was. The report says how many
! chunks each rank took.
!
! CLASSIFICATION (per curve; the rules of benches/tube_search.rs `analyse`).
! Coarse sweep: rodkit_tube_sweep, thick model on 16 fixed Chebyshev
! intervals, rel_tol 1e-7, lambda = 1, 1.005, ..., 1.1, 1.11, ..., 1.5 (61
! stretches), T = 0, p = 0, open ends. A sweep that stops (status < 0) keeps
! the states before it: the sample is classified on the curve up to the last
! solved stretch (status and message recorded). A sample is FAILED (counted,
! reported, no findings) when no tube can be built or fewer than 3 states
! were solved. On the curve: the turning points of y(lambda) ignore steps
! below a noise level (psi: 1e-10/B + 1e-9 max|psi|; radii: 1e-10 B); the
! turn's lambda is the vertex of the parabola through the three samples
! around it.
!   overwind-then-unwind: the first turn of psi is a maximum of s*psi, s the
!     sense psi starts in, with prominence > 1e-3 max|psi| and > 1e-7/B. For
!     SVK walls s must be +1 (the sense of tau0 > 0: the tube overwinds
!     first); for fibre walls either sense counts (family 1 or family 2 as
!     the reference), as in the Rust search.
!   deflate-then-inflate: the outer radius starts decreasing and its first
!     turn is a minimum with prominence > 1e-6 B.
! CONFIRMATION (coarse hits only): two finer sweeps, thick model on 24 and on
! 48 intervals, rel_tol 1e-9, lambda step 0.0025 to 1.1 then 0.005, up to
! the coarse curve's last stretch. A behaviour is confirmed when both show
! it (the same sense for a reversal), their turns agree within 0.01 in
! lambda, the torque-free state is torsionally stable at the turn (dT/dpsi >
! 0 at fixed lambda by a central difference, h = 1e-4/B, rodkit_tube_solve
! on the 24-interval tube) and the fine curve is continuous (largest step of
! psi*B or b/B below 0.02 or below 0.7 times the coarse curve's: a branch
! jump does not shrink with the step). Only confirmed hits go to hits.csv.
!
! CHECKPOINTS. Each finished chunk is written to OUTDIR/checkpoints/
! chunk_<c>.bin (binary: a header naming the format, the rodkit version, the
! seed, the chunk and its samples, then the raw records) through a temporary
! file and rename(2), so a killed run leaves whole files or none (a killed
! rank may leave a chunk_<c>.bin.tmp-rank<r>, overwritten by the next write).
! A restarted run, with any number of ranks, takes every valid chunk file
! instead of computing it (a file of another seed, chunk size or rodkit
! version is recomputed and replaced) and reports how many it skipped; the
! gathered output is bitwise the same.
!
! GATHER. Rank 0 learns which rank took each chunk (MPI_Gatherv of the chunk
! numbers), then receives the chunks in chunk order, each from its rank
! (every rank sends its own in the order it took them, which is increasing:
! no deadlock), and writes each chunk's rows as it comes, checking that
! every sample is there once. So rank 0 needs what every rank needs (the
! records of the chunks it took, about N/P, and the chunk numbers) plus
! one chunk, not a copy of the whole search. The CSVs
! (numbers with 17 significant digits, which read back exactly; an
! inapplicable field is empty) are written through temporary files and
! renamed. Nothing in them depends on P or on time.
!
! MPI: only the main thread calls MPI or rodkit (MPI_Init; rodkit starts no
! threads of its own).
module tube_search_rng
    use, intrinsic :: iso_fortran_env, only: int64, real64
    implicit none
    private
    public :: stream, stream_start, uniform, log_uniform, draws_per_sample

    integer(int64), parameter :: modulus = 2147483647_int64 ! 2^31 - 1
    integer(int64), parameter :: multiplier = 48271_int64
    integer(int64), parameter :: draws_per_sample = 256_int64

    type :: stream
        integer(int64) :: x = 1
        integer(int64) :: used = 0
    end type stream
contains
    ! a^n mod (2^31 - 1) by square-and-multiply (every product < 2^62).
    pure function power_mod(a, n) result(r)
        integer(int64), intent(in) :: a, n
        integer(int64) :: r, b, e
        r = 1
        b = mod(a, modulus)
        e = n
        do while (e > 0)
            if (mod(e, 2_int64) == 1) r = mod(r * b, modulus)
            b = mod(b * b, modulus)
            e = e / 2
        end do
    end function power_mod

    ! The stream of sample `index` (0-based) of the search seeded by `seed`.
    pure function stream_start(seed, index) result(s)
        integer(int64), intent(in) :: seed, index
        type(stream) :: s
        integer(int64) :: x0
        x0 = 1 + mod(abs(seed), modulus - 1)
        s%x = mod(power_mod(multiplier, index * draws_per_sample) * x0, modulus)
        s%used = 0
    end function stream_start

    ! The next draw, uniform in (lo, hi) (x/(2^31 - 1) lies in (0, 1)). A
    ! sample that would use more than its block stops the program: its
    ! draws would overlap the next sample's.
    function uniform(s, lo, hi) result(u)
        type(stream), intent(inout) :: s
        real(real64), intent(in) :: lo, hi
        real(real64) :: u
        s%x = mod(multiplier * s%x, modulus)
        s%used = s%used + 1
        if (s%used > draws_per_sample) error stop 'tube_search_rng: a sample used more than its block of draws'
        u = lo + (hi - lo) * (real(s%x, real64) / real(modulus, real64))
    end function uniform

    function log_uniform(s, lo, hi) result(u)
        type(stream), intent(inout) :: s
        real(real64), intent(in) :: lo, hi
        real(real64) :: u
        u = exp(uniform(s, log(lo), log(hi)))
    end function log_uniform
end module tube_search_rng

module tube_search_model
    use, intrinsic :: iso_c_binding
    use, intrinsic :: iso_fortran_env, only: int64, real64
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use rodkit
    use tube_search_rng
    implicit none
    private
    public :: evaluate, nr, nk, ml, class_name, nclass, nan, csv_header, csv_row, is_hit, &
        k_index, k_class, k_failed, k_conf_rev, k_conf_dip, k_coarse_rev, k_coarse_dip, k_coarse_status, &
        k_fine_status

    integer, parameter :: dp = real64
    integer, parameter :: nclass = 4
    character(len=13), parameter :: class_name(nclass) = [character(len=13) :: &
        'svk_thick', 'svk_thick_inc', 'hgo_fixed', 'hgo_helix']

    ! One sample's record: nk integers, nr reals, a message of ml characters.
    integer, parameter :: nk = 20, nr = 40, ml = 160
    ! Integer fields.
    integer, parameter :: k_index = 1, k_class = 2, k_attempts = 3, k_failed = 4, k_incompressible = 5, &
        k_coarse_status = 6, k_coarse_n = 7, k_coarse_rev = 8, k_sense = 9, k_coarse_dip = 10, &
        k_fine_status = 11, k_f24_n = 12, k_f48_n = 13, k_f24_rev = 14, k_f48_rev = 15, &
        k_f24_dip = 16, k_f48_dip = 17, k_conf_rev = 18, k_conf_dip = 19, k_checked = 20
    ! Real fields: parameters 1-19, coarse 20-26, confirmation 27-39.
    integer, parameter :: r_inner = 1, r_outer = 2, r_tau0 = 3, r_e2 = 4, r_e3 = 5, r_nu12 = 6, &
        r_nu13 = 7, r_nu23 = 8, r_g12 = 9, r_g13 = 10, r_g23 = 11, r_lame = 12, &
        r_b1 = 13, r_k11 = 14, r_k21 = 15, r_b2 = 16, r_k12 = 17, r_k22 = 18, &
        r_c_to = 20, r_c_jump = 21, r_c_rev_lam = 22, r_c_rev_peak = 23, r_c_dip_lam = 24, &
        r_c_dip_depth = 25, r_c_dip_rise = 26, &
        r_f24_to = 27, r_f48_to = 28, r_f24_rev_lam = 29, r_f48_rev_lam = 30, r_f24_rev_peak = 31, &
        r_f24_dip_lam = 32, r_f48_dip_lam = 33, r_f24_dip_depth = 34, r_f24_dip_rise = 35, &
        r_f24_jump = 36, r_dt_rev = 37, r_dt_dip = 38

    ! What one curve shows.
    type :: findings
        integer :: n = 0
        integer :: rev = 0, sense = 0, dip = 0
        integer :: rev_idx = 0, dip_idx = 0
        real(dp) :: solved_to, rev_lam, rev_peak, dip_lam, dip_depth, dip_rise, max_jump
    end type findings

    ! Sweep settings: coarse, then the two confirmation grids.
    integer(c_int64_t), parameter :: coarse_intervals = 16, fine_intervals(2) = [24, 48]
    real(dp), parameter :: coarse_tol = 1.0e-7_dp, fine_tol = 1.0e-9_dp
contains
    function nan() result(x)
        real(dp) :: x
        x = ieee_value(0.0_dp, ieee_quiet_nan)
    end function nan

    ! Stretches 1 -> lam_max: steps h1 up to 1.1, then h2, as multiples of the
    ! step from 1 and from 1.1; the last one clipped to lam_max.
    subroutine stretch_grid(lam_max, h1, h2, lams, n)
        real(dp), intent(in) :: lam_max, h1, h2
        real(dp), intent(out) :: lams(:)
        integer, intent(out) :: n
        real(dp) :: l
        integer :: k
        n = 1
        lams(1) = 1.0_dp
        k = 0
        do
            if (lams(n) >= lam_max - 1.0e-9_dp .or. n >= size(lams)) exit
            k = k + 1
            if (1.0_dp + real(k, dp) * h1 <= 1.1_dp + 1.0e-9_dp) then
                l = 1.0_dp + real(k, dp) * h1
            else
                l = 1.1_dp + real(k - nint(0.1_dp / h1), dp) * h2
            end if
            n = n + 1
            lams(n) = min(l, lam_max)
        end do
    end subroutine stretch_grid

    ! The first turning point of y(lam) (steps below `noise` ignored): its
    ! sample index (0: none), kind (+1 maximum, -1 minimum), the parabola
    ! vertex (lambda, value) and its prominence (|value - the extreme value
    ! after it, up to the next turn or the end|).
    subroutine first_turn(lam, y, n, noise, idx, kind, lt, vt, prom)
        real(dp), intent(in) :: lam(:), y(:), noise
        integer, intent(in) :: n
        integer, intent(out) :: idx, kind
        real(dp), intent(out) :: lt, vt, prom
        integer :: i, cand, dir, next_idx, last
        real(dp) :: d, x0, x1, x2, y0, y1, y2, d01, d12, c2, xs
        idx = 0
        kind = 0
        lt = nan()
        vt = nan()
        prom = 0.0_dp
        next_idx = 0
        if (n < 3) return
        dir = 0
        cand = 1
        do i = 2, n
            d = y(i) - y(cand)
            if (dir == 0) then
                if (abs(d) > noise) then
                    dir = int(sign(1.0_dp, d))
                    cand = i
                end if
                cycle
            end if
            if (d * real(dir, dp) > 0.0_dp) then
                cand = i
            else if (-d * real(dir, dp) > noise) then
                if (idx == 0) then
                    idx = cand
                    kind = dir
                else
                    next_idx = cand
                    exit
                end if
                dir = -dir
                cand = i
            end if
        end do
        if (idx == 0) return
        lt = lam(idx)
        vt = y(idx)
        if (idx > 1 .and. idx < n) then
            x0 = lam(idx - 1); x1 = lam(idx); x2 = lam(idx + 1)
            y0 = y(idx - 1); y1 = y(idx); y2 = y(idx + 1)
            d01 = (y1 - y0) / (x1 - x0)
            d12 = (y2 - y1) / (x2 - x1)
            c2 = (d12 - d01) / (x2 - x0)
            if (abs(c2) > 0.0_dp) then
                xs = 0.5_dp * (x0 + x1) - d01 / (2.0_dp * c2)
                if (xs > x0 .and. xs < x2) then
                    lt = xs
                    vt = y0 + d01 * (xs - x0) + c2 * (xs - x0) * (xs - x1)
                end if
            end if
        end if
        last = n
        if (next_idx > 0) last = next_idx
        if (kind > 0) then
            prom = abs(vt - minval(y(idx:last)))
        else
            prom = abs(vt - maxval(y(idx:last)))
        end if
    end subroutine first_turn

    ! The sense y starts moving in (steps below `noise` ignored), 0 if none.
    integer function start_dir(y, n, noise)
        real(dp), intent(in) :: y(:), noise
        integer, intent(in) :: n
        integer :: i
        start_dir = 0
        do i = 2, n
            if (abs(y(i) - y(1)) > noise) then
                start_dir = int(sign(1.0_dp, y(i) - y(1)))
                return
            end if
        end do
    end function start_dir

    ! The findings of one curve (n solved states); any_sense: a reversal in
    ! either sense counts (fibre walls), else only s = +1.
    function analyse(states, n, outer, any_sense) result(f)
        type(rodkit_tube_state), intent(in) :: states(:)
        integer, intent(in) :: n
        real(dp), intent(in) :: outer
        logical, intent(in) :: any_sense
        type(findings) :: f
        real(dp) :: lam(n), psi(n), b(n), scale, noise, lt, vt, prom
        integer :: idx, kind, i, s
        f%n = n
        f%solved_to = nan(); f%rev_lam = nan(); f%rev_peak = nan()
        f%dip_lam = nan(); f%dip_depth = nan(); f%dip_rise = nan(); f%max_jump = nan()
        if (n < 1) return
        do i = 1, n
            lam(i) = states(i)%stretch
            psi(i) = states(i)%twist
            b(i) = states(i)%deformed_outer_radius
        end do
        f%solved_to = lam(n)
        f%max_jump = 0.0_dp
        do i = 2, n
            f%max_jump = max(f%max_jump, abs(psi(i) - psi(i - 1)) * outer, abs(b(i) - b(i - 1)) / outer)
        end do
        if (n < 3) return
        scale = maxval(abs(psi))
        noise = 1.0e-10_dp / outer + 1.0e-9_dp * scale
        s = start_dir(psi, n, noise)
        f%sense = s
        call first_turn(lam, psi, n, noise, idx, kind, lt, vt, prom)
        if (idx > 0 .and. s /= 0) then
            if (prom > 1.0e-3_dp * scale .and. prom * outer > 1.0e-7_dp .and. s * kind > 0 &
                .and. (any_sense .or. s > 0)) then
                f%rev = 1
                f%rev_idx = idx
                f%rev_lam = lt
                f%rev_peak = real(s, dp) * vt * outer
            end if
        end if
        noise = 1.0e-10_dp * outer
        call first_turn(lam, b, n, noise, idx, kind, lt, vt, prom)
        if (idx > 0 .and. kind < 0 .and. start_dir(b, n, noise) < 0 .and. prom > 1.0e-6_dp * outer) then
            f%dip = 1
            f%dip_idx = idx
            f%dip_lam = lt
            f%dip_depth = (outer - vt) / outer
            f%dip_rise = (b(n) - vt) / outer
        end if
    end function analyse

    ! The first message of a sample is kept (later ones are dropped).
    subroutine note(msg, text)
        character(len=ml), intent(inout) :: msg
        character(len=*), intent(in) :: text
        if (len_trim(msg) == 0) msg = text
    end subroutine note

    ! Draw sample `index` into its parameters (r) and build its coarse tube:
    ! the tube handle, or c_null_ptr when it failed (k(k_failed) = 1).
    subroutine draw(seed, index, k, r, spec, tube, msg)
        integer(int64), intent(in) :: seed, index
        integer(int64), intent(inout) :: k(nk)
        real(dp), intent(inout) :: r(nr)
        type(rodkit_tube_spec), intent(out) :: spec
        type(c_ptr), intent(out) :: tube
        character(len=ml), intent(inout) :: msg
        type(stream) :: s
        integer(c_int32_t) :: st
        integer :: cls, attempt
        real(dp), parameter :: deg = acos(-1.0_dp) / 180.0_dp
        character(len=32) :: where

        tube = c_null_ptr
        s = stream_start(seed, index)
        cls = int(mod(index, int(nclass, int64))) + 1
        k(k_class) = cls
        st = rodkit_tube_spec_default(spec)
        if (st < 0) then
            k(k_failed) = 1
            call note(msg, 'rodkit_tube_spec_default: ' // rodkit_last_error())
            return
        end if
        spec%outer_radius = 1.0_dp
        spec%model = RODKIT_TUBE_MODEL_THICK
        spec%rel_tol = coarse_tol
        spec%intervals = coarse_intervals
        r(r_outer) = 1.0_dp
        select case (cls)
        case (1, 2)
            spec%inner_radius = log_uniform(s, 0.02_dp, 0.7_dp)
            spec%material%intrinsic_twist = uniform(s, 0.5_dp, 6.0_dp)
            spec%material%law = RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF
            spec%material%incompressible = merge(1_c_int32_t, 0_c_int32_t, cls == 2)
            spec%material%e1 = 1.0_dp
            do attempt = 1, 100
                k(k_attempts) = attempt
                spec%material%e2 = log_uniform(s, 0.01_dp, 10.0_dp)
                spec%material%e3 = log_uniform(s, 0.01_dp, 10.0_dp)
                spec%material%nu12 = uniform(s, -0.8_dp, 1.2_dp)
                spec%material%nu13 = uniform(s, -0.5_dp, 0.9_dp)
                spec%material%nu23 = uniform(s, -0.5_dp, 0.9_dp)
                spec%material%g12 = log_uniform(s, 0.003_dp, 3.0_dp)
                spec%material%g13 = log_uniform(s, 0.003_dp, 3.0_dp)
                spec%material%g23 = log_uniform(s, 0.003_dp, 3.0_dp)
                st = rodkit_tube_new(spec, tube)
                if (st /= RODKIT_STATUS_ERR_NOT_POSITIVE_DEFINITE) exit
            end do
            r(r_e2) = spec%material%e2; r(r_e3) = spec%material%e3
            r(r_nu12) = spec%material%nu12; r(r_nu13) = spec%material%nu13; r(r_nu23) = spec%material%nu23
            r(r_g12) = spec%material%g12; r(r_g13) = spec%material%g13; r(r_g23) = spec%material%g23
        case default
            spec%material%law = RODKIT_WALL_LAW_KIND_FIBRE_REINFORCED
            spec%material%shear_modulus = 1.0_dp
            if (uniform(s, 0.0_dp, 1.0_dp) < 0.4_dp) then
                spec%material%incompressible = 1
            else
                spec%material%incompressible = 0
                spec%material%lame_lambda = log_uniform(s, 0.3_dp, 300.0_dp)
                r(r_lame) = spec%material%lame_lambda
            end if
            spec%material%fibre_families = 2
            spec%material%fibre1_k1 = log_uniform(s, 0.05_dp, 500.0_dp)
            spec%material%fibre1_k2 = log_uniform(s, 0.01_dp, 30.0_dp)
            spec%material%fibre2_k1 = log_uniform(s, 0.05_dp, 500.0_dp)
            spec%material%fibre2_k2 = log_uniform(s, 0.01_dp, 30.0_dp)
            if (cls == 3) then
                spec%material%fibre1_angle = uniform(s, 1.0_dp, 88.0_dp) * deg
                spec%material%fibre2_angle = -uniform(s, 1.0_dp, 88.0_dp) * deg
                spec%material%intrinsic_twist = 0.0_dp
                spec%inner_radius = uniform(s, 0.3_dp, 0.95_dp)
                r(r_b1) = spec%material%fibre1_angle
                r(r_b2) = spec%material%fibre2_angle
            else
                ! NaN angles: the families follow the helix, hands +1 and -1
                ! (rodkit_wall_material_spec_default's).
                spec%material%fibre1_hand = 1.0_dp
                spec%material%fibre2_hand = -1.0_dp
                spec%material%intrinsic_twist = uniform(s, 0.3_dp, 6.0_dp)
                spec%inner_radius = log_uniform(s, 0.05_dp, 0.9_dp)
            end if
            r(r_k11) = spec%material%fibre1_k1; r(r_k21) = spec%material%fibre1_k2
            r(r_k12) = spec%material%fibre2_k1; r(r_k22) = spec%material%fibre2_k2
            k(k_attempts) = 1
            st = rodkit_tube_new(spec, tube)
        end select
        r(r_inner) = spec%inner_radius
        r(r_tau0) = spec%material%intrinsic_twist
        k(k_incompressible) = spec%material%incompressible
        if (st < 0) then
            k(k_failed) = 1
            k(k_coarse_status) = st
            write (where, '(a, i0, a)') 'rodkit_tube_new (', k(k_attempts), ' draws): '
            call note(msg, trim(where) // rodkit_last_error())
            tube = c_null_ptr
        end if
    end subroutine draw

    ! A torque-free sweep of `tube` over lams(1:n): the states solved, their
    ! number and the status (a message noted on failure).
    subroutine sweep(tube, lams, n, states, done, st, what, msg)
        type(c_ptr), intent(in) :: tube
        real(dp), intent(in) :: lams(:)
        integer, intent(in) :: n
        type(rodkit_tube_state), intent(inout) :: states(:)
        integer, intent(out) :: done
        integer(c_int32_t), intent(out) :: st
        character(len=*), intent(in) :: what
        character(len=ml), intent(inout) :: msg
        type(rodkit_tube_loading) :: loadings(n)
        integer(c_int64_t) :: completed
        integer :: i
        character(len=40) :: where
        do i = 1, n
            st = rodkit_tube_loading_default(loadings(i))
            if (st < 0) then
                done = 0
                call note(msg, what // ': rodkit_tube_loading_default: ' // rodkit_last_error())
                return
            end if
            loadings(i)%axial_control = RODKIT_AXIAL_CONTROL_STRETCH
            loadings(i)%axial = lams(i)
            loadings(i)%torsion_control = RODKIT_TORSION_CONTROL_TORQUE
            loadings(i)%torsion = 0.0_dp
        end do
        completed = 0
        st = rodkit_tube_sweep(tube, loadings, int(n, c_int64_t), states, c_null_funptr, c_null_ptr, completed)
        done = int(completed)
        if (st < 0) then
            if (done > 0) then
                write (where, '(a, a, f0.4, a)') what, ' stopped after lambda ', states(done)%stretch, ':'
            else
                write (where, '(a, a)') what, ' failed at the start:'
            end if
            call note(msg, trim(where) // ' ' // rodkit_last_error())
        else if (st > 0) then
            call note(msg, what // ': ' // rodkit_status_message(st))
        end if
    end subroutine sweep

    ! dT/dpsi at fixed stretch lam and twist psi (central difference, h =
    ! 1e-4/B): NaN (status noted) when a solve fails.
    function torsional_stiffness(tube, lam, psi, outer, st, msg) result(dt)
        type(c_ptr), intent(in) :: tube
        real(dp), intent(in) :: lam, psi, outer
        integer(c_int32_t), intent(inout) :: st
        character(len=ml), intent(inout) :: msg
        real(dp) :: dt, t(2), h
        type(rodkit_tube_loading) :: l
        type(rodkit_tube_state) :: out
        integer :: j
        integer(c_int32_t) :: s
        dt = nan()
        h = 1.0e-4_dp / outer
        s = rodkit_tube_loading_default(l)
        if (s < 0) then
            st = s
            call note(msg, 'dT/dpsi: rodkit_tube_loading_default: ' // rodkit_last_error())
            return
        end if
        l%axial_control = RODKIT_AXIAL_CONTROL_STRETCH
        l%axial = lam
        l%torsion_control = RODKIT_TORSION_CONTROL_TWIST
        do j = 1, 2
            l%torsion = psi + real(2 * j - 3, dp) * h
            s = rodkit_tube_solve(tube, l, out)
            if (s < 0) then
                st = s
                call note(msg, 'dT/dpsi: rodkit_tube_solve: ' // rodkit_last_error())
                return
            end if
            t(j) = out%torque
        end do
        dt = (t(2) - t(1)) / (2.0_dp * h)
    end function torsional_stiffness

    ! Sample `index`: draw, coarse sweep, classification, confirmation.
    subroutine evaluate(seed, index, k, r, msg)
        integer(int64), intent(in) :: seed, index
        integer(int64), intent(out) :: k(nk)
        real(dp), intent(out) :: r(nr)
        character(len=ml), intent(out) :: msg
        integer, parameter :: max_pts = 200
        type(rodkit_tube_spec) :: spec
        type(c_ptr) :: tube, fine_tube(2)
        type(rodkit_tube_state) :: states(max_pts), fstates(max_pts, 2)
        type(findings) :: c, f(2)
        real(dp) :: lams(max_pts), outer
        integer :: n, done, j, fdone(2)
        integer(c_int32_t) :: st, fst
        logical :: fibre, rev_ok, dip_ok, continuous
        character(len=12) :: label

        k = 0
        r = nan()
        msg = ''
        k(k_index) = index
        call draw(seed, index, k, r, spec, tube, msg)
        if (k(k_failed) /= 0) return
        outer = spec%outer_radius
        fibre = spec%material%law == RODKIT_WALL_LAW_KIND_FIBRE_REINFORCED

        ! Coarse sweep.
        call stretch_grid(1.5_dp, 0.005_dp, 0.01_dp, lams, n)
        call sweep(tube, lams, n, states, done, st, 'coarse', msg)
        call rodkit_tube_free(tube)
        k(k_coarse_status) = st
        k(k_coarse_n) = done
        if (done < 3) then
            k(k_failed) = 1
            call note(msg, 'coarse: fewer than 3 states')
            return
        end if
        c = analyse(states, done, outer, fibre)
        k(k_coarse_rev) = c%rev
        k(k_sense) = c%sense
        k(k_coarse_dip) = c%dip
        r(r_c_to) = c%solved_to; r(r_c_jump) = c%max_jump
        r(r_c_rev_lam) = c%rev_lam; r(r_c_rev_peak) = c%rev_peak
        r(r_c_dip_lam) = c%dip_lam; r(r_c_dip_depth) = c%dip_depth; r(r_c_dip_rise) = c%dip_rise
        if (c%rev == 0 .and. c%dip == 0) return

        ! Confirmation on the finer grids.
        k(k_checked) = 1
        call stretch_grid(min(c%solved_to, 1.5_dp), 0.0025_dp, 0.005_dp, lams, n)
        fst = 0
        do j = 1, 2
            spec%intervals = fine_intervals(j)
            spec%rel_tol = fine_tol
            st = rodkit_tube_new(spec, fine_tube(j))
            if (st < 0) then
                fst = st
                call note(msg, 'fine: rodkit_tube_new: ' // rodkit_last_error())
                fdone(j) = 0
                fine_tube(j) = c_null_ptr
                f(j) = analyse(fstates(:, j), 0, outer, fibre)
                cycle
            end if
            write (label, '(a, i0)') 'fine n=', fine_intervals(j)
            call sweep(fine_tube(j), lams, n, fstates(:, j), fdone(j), st, trim(label), msg)
            if (st < 0 .and. fst == 0) fst = st
            f(j) = analyse(fstates(:, j), fdone(j), outer, fibre)
        end do
        k(k_f24_n) = fdone(1); k(k_f48_n) = fdone(2)
        k(k_f24_rev) = f(1)%rev; k(k_f48_rev) = f(2)%rev
        k(k_f24_dip) = f(1)%dip; k(k_f48_dip) = f(2)%dip
        r(r_f24_to) = f(1)%solved_to; r(r_f48_to) = f(2)%solved_to
        r(r_f24_rev_lam) = f(1)%rev_lam; r(r_f48_rev_lam) = f(2)%rev_lam; r(r_f24_rev_peak) = f(1)%rev_peak
        r(r_f24_dip_lam) = f(1)%dip_lam; r(r_f48_dip_lam) = f(2)%dip_lam
        r(r_f24_dip_depth) = f(1)%dip_depth; r(r_f24_dip_rise) = f(1)%dip_rise
        r(r_f24_jump) = f(1)%max_jump
        continuous = .false.
        if (f(1)%n >= 3) continuous = f(1)%max_jump < 0.02_dp .or. f(1)%max_jump < 0.7_dp * c%max_jump
        if (c_associated(fine_tube(1))) then
            if (c%rev == 1 .and. f(1)%rev == 1) r(r_dt_rev) = torsional_stiffness(fine_tube(1), &
                fstates(f(1)%rev_idx, 1)%stretch, fstates(f(1)%rev_idx, 1)%twist, outer, fst, msg)
            if (c%dip == 1 .and. f(1)%dip == 1) r(r_dt_dip) = torsional_stiffness(fine_tube(1), &
                fstates(f(1)%dip_idx, 1)%stretch, fstates(f(1)%dip_idx, 1)%twist, outer, fst, msg)
        end if
        do j = 1, 2
            call rodkit_tube_free(fine_tube(j))
        end do
        k(k_fine_status) = fst
        rev_ok = c%rev == 1 .and. f(1)%rev == 1 .and. f(2)%rev == 1
        if (rev_ok) rev_ok = f(1)%sense == c%sense .and. f(2)%sense == c%sense &
            .and. abs(f(1)%rev_lam - f(2)%rev_lam) < 0.01_dp .and. r(r_dt_rev) > 0.0_dp .and. continuous
        dip_ok = c%dip == 1 .and. f(1)%dip == 1 .and. f(2)%dip == 1
        if (dip_ok) dip_ok = abs(f(1)%dip_lam - f(2)%dip_lam) < 0.01_dp .and. r(r_dt_dip) > 0.0_dp .and. continuous
        k(k_conf_rev) = merge(1, 0, rev_ok)
        k(k_conf_dip) = merge(1, 0, dip_ok)
    end subroutine evaluate

    logical function is_hit(k)
        integer(int64), intent(in) :: k(nk)
        is_hit = k(k_conf_rev) == 1 .or. k(k_conf_dip) == 1
    end function is_hit

    function csv_header() result(h)
        character(len=:), allocatable :: h
        h = 'index,class,failed,draws,inner,outer,tau0,incompressible,e2,e3,nu12,nu13,nu23,g12,g13,g23,' // &
            'lame_lambda,fibre1_angle,fibre1_k1,fibre1_k2,fibre2_angle,fibre2_k1,fibre2_k2,' // &
            'coarse_status,coarse_states,coarse_solved_to,coarse_max_jump,coarse_rev,rev_sense,' // &
            'coarse_rev_lam,coarse_rev_peak_psiB,coarse_dip,coarse_dip_lam,coarse_dip_depth,coarse_dip_rise,' // &
            'checked,fine_status,fine24_states,fine48_states,fine24_solved_to,fine48_solved_to,' // &
            'fine24_rev,fine48_rev,fine24_rev_lam,fine48_rev_lam,fine24_rev_peak_psiB,' // &
            'fine24_dip,fine48_dip,fine24_dip_lam,fine48_dip_lam,fine24_dip_depth,fine24_dip_rise,' // &
            'fine24_max_jump,dTdpsi_rev,dTdpsi_dip,confirmed_rev,confirmed_dip,message'
    end function csv_header

    ! A real with 17 significant digits (reads back exactly); NaN: empty.
    function fr(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buf
        if (ieee_is_nan(x)) then
            s = ''
        else
            write (buf, '(es24.16e3)') x
            s = trim(adjustl(buf))
        end if
    end function fr

    function fi(i) result(s)
        integer(int64), intent(in) :: i
        character(len=:), allocatable :: s
        character(len=24) :: buf
        write (buf, '(i0)') i
        s = trim(buf)
    end function fi

    ! The message without the CSV's separators and quotes.
    function clean(text) result(s)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: s
        integer :: i
        s = trim(text)
        do i = 1, len(s)
            select case (s(i:i))
            case (',')
                s(i:i) = ';'
            case ('"')
                s(i:i) = ''''
            case default
                if (iachar(s(i:i)) < 32) s(i:i) = ' '
            end select
        end do
    end function clean

    function csv_row(k, r, msg) result(row)
        integer(int64), intent(in) :: k(nk)
        real(dp), intent(in) :: r(nr)
        character(len=ml), intent(in) :: msg
        character(len=:), allocatable :: row
        character(len=1), parameter :: c = ','
        row = fi(k(k_index)) // c // trim(class_name(k(k_class))) // c // fi(k(k_failed)) // c // fi(k(k_attempts)) &
            // c // fr(r(r_inner)) // c // fr(r(r_outer)) // c // fr(r(r_tau0)) // c // fi(k(k_incompressible)) &
            // c // fr(r(r_e2)) // c // fr(r(r_e3)) // c // fr(r(r_nu12)) // c // fr(r(r_nu13)) // c // fr(r(r_nu23)) &
            // c // fr(r(r_g12)) // c // fr(r(r_g13)) // c // fr(r(r_g23)) // c // fr(r(r_lame)) &
            // c // fr(r(r_b1)) // c // fr(r(r_k11)) // c // fr(r(r_k21)) &
            // c // fr(r(r_b2)) // c // fr(r(r_k12)) // c // fr(r(r_k22)) &
            // c // fi(k(k_coarse_status)) // c // fi(k(k_coarse_n)) // c // fr(r(r_c_to)) // c // fr(r(r_c_jump)) &
            // c // fi(k(k_coarse_rev)) // c // fi(k(k_sense)) // c // fr(r(r_c_rev_lam)) // c // fr(r(r_c_rev_peak)) &
            // c // fi(k(k_coarse_dip)) // c // fr(r(r_c_dip_lam)) // c // fr(r(r_c_dip_depth)) &
            // c // fr(r(r_c_dip_rise)) &
            // c // fi(k(k_checked)) // c // fi(k(k_fine_status)) // c // fi(k(k_f24_n)) // c // fi(k(k_f48_n)) &
            // c // fr(r(r_f24_to)) // c // fr(r(r_f48_to)) &
            // c // fi(k(k_f24_rev)) // c // fi(k(k_f48_rev)) // c // fr(r(r_f24_rev_lam)) // c // fr(r(r_f48_rev_lam)) &
            // c // fr(r(r_f24_rev_peak)) &
            // c // fi(k(k_f24_dip)) // c // fi(k(k_f48_dip)) // c // fr(r(r_f24_dip_lam)) // c // fr(r(r_f48_dip_lam)) &
            // c // fr(r(r_f24_dip_depth)) // c // fr(r(r_f24_dip_rise)) &
            // c // fr(r(r_f24_jump)) // c // fr(r(r_dt_rev)) // c // fr(r(r_dt_dip)) &
            // c // fi(k(k_conf_rev)) // c // fi(k(k_conf_dip)) // c // clean(msg)
    end function csv_row
end module tube_search_model

module tube_search_files
    use, intrinsic :: iso_c_binding
    use, intrinsic :: iso_fortran_env, only: int32, int64, real64
    use tube_search_model, only: nr, nk, ml
    use rodkit, only: RODKIT_VERSION_STRING
    implicit none
    private
    public :: make_dir, rename_file, chunk_path, write_chunk, read_chunk

    ! The checkpoint format: change it with the search's settings. The
    ! header also names the rodkit version: another version's chunks are
    ! recomputed.
    character(len=16), parameter :: magic = 'rodkit-ts-v1    '
    character(len=32), parameter :: version = RODKIT_VERSION_STRING

    interface
        function c_mkdir(path, mode) result(r) bind(c, name='mkdir')
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: r
        end function c_mkdir
        function c_rename(old, new) result(r) bind(c, name='rename')
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: old(*), new(*)
            integer(c_int) :: r
        end function c_rename
    end interface
contains
    ! mkdir(path, 0755); an existing directory is fine (the later opens
    ! report a real problem).
    subroutine make_dir(path)
        character(len=*), intent(in) :: path
        integer(c_int) :: r
        r = c_mkdir(trim(path) // c_null_char, int(o'755', c_int))
        if (r /= 0) r = 0
    end subroutine make_dir

    logical function rename_file(old, new)
        character(len=*), intent(in) :: old, new
        rename_file = c_rename(trim(old) // c_null_char, trim(new) // c_null_char) == 0
    end function rename_file

    function chunk_path(dir, chunk) result(p)
        character(len=*), intent(in) :: dir
        integer(int64), intent(in) :: chunk
        character(len=:), allocatable :: p
        character(len=32) :: name
        write (name, '(a, i8.8, a)') 'chunk_', chunk, '.bin'
        p = trim(dir) // '/checkpoints/' // trim(name)
    end function chunk_path

    ! Write a chunk's records to its checkpoint: a temporary file of this
    ! rank, then rename(2) over the final name (atomic on one file system).
    subroutine write_chunk(dir, rank, seed, chunk, first, count, k, r, msg, ok)
        character(len=*), intent(in) :: dir
        integer, intent(in) :: rank
        integer(int64), intent(in) :: seed, chunk, first, count
        integer(int64), intent(in) :: k(:, :)
        real(real64), intent(in) :: r(:, :)
        character(len=ml), intent(in) :: msg(:)
        logical, intent(out) :: ok
        character(len=:), allocatable :: final, tmp
        character(len=16) :: suffix
        integer :: u, ios
        final = chunk_path(dir, chunk)
        write (suffix, '(a, i0)') '.tmp-rank', rank
        tmp = final // trim(suffix)
        open (newunit=u, file=tmp, access='stream', form='unformatted', status='replace', action='write', iostat=ios)
        ok = ios == 0
        if (.not. ok) return
        write (u, iostat=ios) magic, version, seed, chunk, first, count, int(nk, int32), int(nr, int32), int(ml, int32), &
            k(:, 1:count), r(:, 1:count), msg(1:count)
        ok = ios == 0
        close (u, iostat=ios)
        ok = ok .and. ios == 0
        if (ok) ok = rename_file(tmp, final)
    end subroutine write_chunk

    ! Read a chunk's checkpoint if it exists and matches (format, seed,
    ! chunk, samples): found; a mismatching file: stale.
    subroutine read_chunk(dir, seed, chunk, first, count, k, r, msg, found, stale)
        character(len=*), intent(in) :: dir
        integer(int64), intent(in) :: seed, chunk, first, count
        integer(int64), intent(inout) :: k(:, :)
        real(real64), intent(inout) :: r(:, :)
        character(len=ml), intent(inout) :: msg(:)
        logical, intent(out) :: found, stale
        character(len=16) :: m
        character(len=32) :: v
        integer(int64) :: s, c, f, n
        integer(int32) :: a, b, d
        integer :: u, ios
        logical :: there
        found = .false.
        stale = .false.
        inquire (file=chunk_path(dir, chunk), exist=there)
        if (.not. there) return
        stale = .true.
        open (newunit=u, file=chunk_path(dir, chunk), access='stream', form='unformatted', status='old', &
            action='read', iostat=ios)
        if (ios /= 0) return
        read (u, iostat=ios) m, v, s, c, f, n, a, b, d
        if (ios == 0 .and. m == magic .and. v == version .and. s == seed .and. c == chunk .and. f == first .and. n == count &
            .and. a == nk .and. b == nr .and. d == ml) then
            read (u, iostat=ios) k(:, 1:count), r(:, 1:count), msg(1:count)
            found = ios == 0
            stale = .not. found
        end if
        close (u, iostat=ios)
    end subroutine read_chunk
end module tube_search_files

program mpi_tube_search
    use, intrinsic :: iso_fortran_env, only: int64, real64, output_unit
    use, intrinsic :: iso_c_binding, only: c_ptr, c_f_pointer
    use mpi_f08
    use rodkit, only: RODKIT_VERSION_STRING
    use tube_search_model
    use tube_search_files
    implicit none
    integer :: rank, nranks, ios, j
    integer(int64) :: nsamples, seed, chunk_size, nchunks, c, first, cnt, mine, pos, i, hits_rev, hits_dip
    integer(int64) :: coarse_rev, coarse_dip, failed, stopped, counts(nclass), fine_failed
    integer(int64) :: skipped(2), computed, totals(4), taken, one
    ! The counter's value as fetched: an RMA result buffer (MPI 4.1,
    ! 19.1.17: asynchronous, and synchronised after the epoch).
    integer(int64), asynchronous :: next
    integer(int64), allocatable :: taken_by(:)
    integer(int64), pointer :: counter
    type(c_ptr) :: base
    type(MPI_Win) :: win
    integer(MPI_ADDRESS_KIND) :: window_size
    integer(int64), allocatable :: k(:, :)
    real(real64), allocatable :: r(:, :)
    character(len=ml), allocatable :: msg(:)
    integer, allocatable :: recv(:), displ(:), owner(:)
    integer(int64), allocatable :: mychunks(:), chunks(:), kc(:, :)
    real(real64), allocatable :: rc(:, :)
    character(len=ml), allocatable :: mc(:)
    integer :: u_all, u_hits
    character(len=1024) :: outdir
    real(real64) :: t0, t_compute, t_max, t_sum, t_total
    logical :: found, stale, ok
    integer(int64) :: settings(4)

    call MPI_Init()
    call MPI_Comm_rank(MPI_COMM_WORLD, rank)
    call MPI_Comm_size(MPI_COMM_WORLD, nranks)
    t0 = MPI_Wtime()

    ! Arguments: parsed by rank 0, broadcast (the MPI standard does not
    ! promise the command line to the other ranks).
    settings = [256_int64, 1_int64, 8_int64, 0_int64]
    outdir = ''
    if (rank == 0) call parse_arguments(settings, outdir)
    call MPI_Bcast(settings, 4, MPI_INTEGER8, 0, MPI_COMM_WORLD)
    call MPI_Bcast(outdir, len(outdir), MPI_CHARACTER, 0, MPI_COMM_WORLD)
    if (settings(4) /= 0) then
        call MPI_Finalize()
        stop 2
    end if
    nsamples = settings(1)
    seed = settings(2)
    chunk_size = settings(3)
    nchunks = (nsamples + chunk_size - 1) / chunk_size
    if (rank == 0) then
        call make_dir(outdir)
        call make_dir(trim(outdir) // '/checkpoints')
    end if
    call MPI_Barrier(MPI_COMM_WORLD)

    ! The chunk counter: 8 bytes in rank 0's window, set to 0 before any
    ! rank takes from it (the barrier).
    window_size = 0
    if (rank == 0) window_size = 8
    call MPI_Win_allocate(window_size, 8, MPI_INFO_NULL, MPI_COMM_WORLD, base, win)
    if (rank == 0) then
        call c_f_pointer(base, counter)
        call MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, win)
        counter = 0
        call MPI_F_sync_reg(counter)
        call MPI_Win_unlock(0, win)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)

    ! Take chunks until none is left; this rank's records in the order it
    ! took them (each carries its sample index), and the chunks' numbers.
    allocate (k(nk, chunk_size), r(nr, chunk_size), msg(chunk_size), mychunks(nchunks))
    mine = 0
    taken = 0
    skipped = 0
    computed = 0
    one = 1
    do
        call MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, win)
        call MPI_Fetch_and_op(one, next, MPI_INTEGER8, 0, 0_MPI_ADDRESS_KIND, MPI_SUM, win)
        call MPI_Win_unlock(0, win)
        call MPI_F_sync_reg(next)
        if (next >= nchunks) exit
        c = next
        taken = taken + 1
        mychunks(taken) = c
        first = c * chunk_size
        cnt = min(chunk_size, nsamples - first)
        call reserve(mine + cnt)
        pos = mine
        call read_chunk(outdir, seed, c, first, cnt, k(:, pos + 1:), r(:, pos + 1:), msg(pos + 1:), found, stale)
        if (found) then
            skipped(1) = skipped(1) + cnt
            skipped(2) = skipped(2) + 1
        else
            if (stale) print '(a, i0, a)', 'rank ', rank, ': ' // chunk_path(outdir, c) // &
                ' is not a checkpoint of this search: recomputed'
            do i = 1, cnt
                call evaluate(seed, first + i - 1, k(:, pos + i), r(:, pos + i), msg(pos + i))
            end do
            computed = computed + cnt
            call write_chunk(outdir, rank, seed, c, first, cnt, k(:, pos + 1:), r(:, pos + 1:), msg(pos + 1:), ok)
            if (.not. ok) then
                print '(a, i0, a)', 'rank ', rank, ': cannot write ' // chunk_path(outdir, c)
                call MPI_Abort(MPI_COMM_WORLD, 1)
            end if
        end if
        mine = mine + cnt
    end do
    ! This rank's work ends here: MPI_Win_free waits for every rank.
    t_compute = MPI_Wtime() - t0
    call MPI_Win_free(win)

    call MPI_Reduce(t_compute, t_max, 1, MPI_DOUBLE_PRECISION, MPI_MAX, 0, MPI_COMM_WORLD)
    call MPI_Reduce(t_compute, t_sum, 1, MPI_DOUBLE_PRECISION, MPI_SUM, 0, MPI_COMM_WORLD)
    call MPI_Reduce([skipped, computed, mine], totals, 4, MPI_INTEGER8, MPI_SUM, 0, MPI_COMM_WORLD)

    ! Who took each chunk: rank 0 gathers every rank's chunk numbers (a
    ! rank's records are its chunks' samples in the order it took them).
    allocate (taken_by(nranks), recv(nranks), displ(nranks))
    call MPI_Gather(taken, 1, MPI_INTEGER8, taken_by, 1, MPI_INTEGER8, 0, MPI_COMM_WORLD)
    if (rank == 0) then
        ! The counter hands out each chunk once: anything else is a bug (and
        ! would overflow the buffer below), so it stops the job.
        if (sum(taken_by) /= nchunks) call give_up('the ranks took another number of chunks than there are')
        recv = int(taken_by)
        displ(1) = 0
        do j = 2, nranks
            displ(j) = displ(j - 1) + recv(j - 1)
        end do
        allocate (chunks(nchunks), owner(nchunks))
    else
        allocate (chunks(1), owner(1))
    end if
    call MPI_Gatherv(mychunks, int(taken), MPI_INTEGER8, chunks, recv, displ, MPI_INTEGER8, 0, MPI_COMM_WORLD)

    if (rank /= 0) then
        ! Send this rank's chunks to rank 0, in the order taken.
        pos = 0
        do j = 1, int(taken)
            cnt = min(chunk_size, nsamples - mychunks(j) * chunk_size)
            call MPI_Send(k(:, pos + 1:pos + cnt), int(cnt) * nk, MPI_INTEGER8, 0, 1, MPI_COMM_WORLD)
            call MPI_Send(r(:, pos + 1:pos + cnt), int(cnt) * nr, MPI_DOUBLE_PRECISION, 0, 2, MPI_COMM_WORLD)
            call MPI_Send(msg(pos + 1:pos + cnt), int(cnt) * ml, MPI_CHARACTER, 0, 3, MPI_COMM_WORLD)
            pos = pos + cnt
        end do
    else
        ! Every chunk taken exactly once.
        owner = -1
        do j = 1, nranks
            do i = displ(j) + 1, displ(j) + recv(j)
                c = chunks(i)
                if (c < 0 .or. c >= nchunks) call give_up('a rank reports a chunk out of range')
                if (owner(c + 1) /= -1) call give_up('a chunk was taken twice')
                owner(c + 1) = j - 1
            end do
        end do
        if (any(owner == -1)) call give_up('a chunk was taken by no rank')
        allocate (kc(nk, chunk_size), rc(nr, chunk_size), mc(chunk_size))
        call open_csv(trim(outdir) // '/samples.csv', u_all)
        call open_csv(trim(outdir) // '/hits.csv', u_hits)
        counts = 0
        failed = 0; stopped = 0; coarse_rev = 0; coarse_dip = 0; hits_rev = 0; hits_dip = 0; fine_failed = 0
        pos = 0
        do c = 0, nchunks - 1
            first = c * chunk_size
            cnt = min(chunk_size, nsamples - first)
            if (owner(c + 1) == 0) then
                ! Its own chunk: the rows straight from its records.
                call take_chunk(k(:, pos + 1:pos + cnt), r(:, pos + 1:pos + cnt), msg(pos + 1:pos + cnt), first, cnt)
                pos = pos + cnt
            else
                call MPI_Recv(kc, int(cnt) * nk, MPI_INTEGER8, owner(c + 1), 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE)
                call MPI_Recv(rc, int(cnt) * nr, MPI_DOUBLE_PRECISION, owner(c + 1), 2, MPI_COMM_WORLD, &
                    MPI_STATUS_IGNORE)
                call MPI_Recv(mc, int(cnt) * ml, MPI_CHARACTER, owner(c + 1), 3, MPI_COMM_WORLD, MPI_STATUS_IGNORE)
                call take_chunk(kc, rc, mc, first, cnt)
            end if
        end do
        call close_csv(trim(outdir) // '/samples.csv', u_all)
        call close_csv(trim(outdir) // '/hits.csv', u_hits)

        t_total = MPI_Wtime() - t0
        print '(a, i0, a, i0, a, i0, a, i0, a, i0, a)', 'mpi_tube_search (rodkit ' // RODKIT_VERSION_STRING // &
            '): ', nsamples, ' samples, seed ', seed, ', ', nchunks, ' chunks of ', chunk_size, ' on ', nranks, &
            ' ranks -> ' // trim(outdir)
        print '(a, 4(a, a, a, i0))', 'classes:', (' ', trim(class_name(j)), ' ', counts(j), j = 1, nclass)
        if (totals(1) > 0) then
            print '(a, i0, a, i0, a, i0, a)', 'restart: skipped ', totals(1), ' samples (', totals(2), &
                ' chunks) found in checkpoints; computed ', totals(3), ' samples'
        else
            print '(a, i0, a)', 'checkpoints: none found; computed ', totals(3), ' samples'
        end if
        print '(a, i0, a, i0)', 'failed: ', failed, ' samples (no tube or fewer than 3 states; listed with ' // &
            'their messages in samples.csv); sweeps stopped before lambda = 1.5: ', stopped
        print '(a, i0, a, i0)', 'overwind-then-unwind: coarse ', coarse_rev, ', confirmed ', hits_rev
        print '(a, i0, a, i0)', 'deflate-then-inflate: coarse ', coarse_dip, ', confirmed ', hits_dip
        print '(a, i0, a)', 'confirmation: ', fine_failed, ' candidates had a fine sweep or solve stop ' // &
            '(not confirmed unless both fine curves show the turn)'
        print '(a, *(1x, i0))', 'chunks taken per rank:', taken_by
        print '(a)', 'time: ' // secs(t_total) // ' s (slowest rank ' // secs(t_max) // ' s; all ranks ' // &
            secs(t_sum) // ' s)'
        if (totals(3) > 0) print '(a, es10.3, a)', 'cost: ', t_sum / real(totals(3), real64), &
            ' s per computed sample (all ranks'' time / samples computed)'
        flush (output_unit)
    end if
    call MPI_Finalize()

contains
    ! Room for n records in k, r and msg (doubled when short; kept).
    subroutine reserve(n)
        integer(int64), intent(in) :: n
        integer(int64) :: cap
        integer(int64), allocatable :: k2(:, :)
        real(real64), allocatable :: r2(:, :)
        character(len=ml), allocatable :: m2(:)
        if (n <= size(msg, kind=int64)) return
        cap = max(n, 2 * size(msg, kind=int64))
        allocate (k2(nk, cap), r2(nr, cap), m2(cap))
        k2(:, :mine) = k(:, :mine)
        r2(:, :mine) = r(:, :mine)
        m2(:mine) = msg(:mine)
        call move_alloc(k2, k)
        call move_alloc(r2, r)
        call move_alloc(m2, msg)
    end subroutine reserve

    function secs(t) result(text)
        real(real64), intent(in) :: t
        character(len=:), allocatable :: text
        character(len=16) :: buf
        write (buf, '(f16.3)') t
        text = trim(adjustl(buf))
    end function secs

    subroutine parse_arguments(settings, outdir)
        integer(int64), intent(inout) :: settings(4)
        character(len=*), intent(inout) :: outdir
        character(len=1024) :: arg, val
        integer :: a, n, ios
        n = command_argument_count()
        a = 1
        do while (a <= n)
            call get_command_argument(a, arg)
            select case (trim(arg))
            case ('--samples', '--seed', '--chunk')
                if (a == n) then
                    settings(4) = 1
                    exit
                end if
                call get_command_argument(a + 1, val)
                select case (trim(arg))
                case ('--samples')
                    read (val, *, iostat=ios) settings(1)
                case ('--seed')
                    read (val, *, iostat=ios) settings(2)
                case default
                    read (val, *, iostat=ios) settings(3)
                end select
                if (ios /= 0) settings(4) = 1
                a = a + 2
            case default
                if (arg(1:1) == '-' .or. len_trim(outdir) > 0) then
                    settings(4) = 1
                    exit
                end if
                outdir = arg
                a = a + 1
            end select
        end do
        if (len_trim(outdir) == 0 .or. settings(1) < 1 .or. settings(2) < 0 .or. settings(3) < 1) settings(4) = 1
        if (settings(4) /= 0) print '(a)', 'usage: mpirun -np P f_mpi_tube_search [--samples N >= 1] ' // &
            '[--seed S >= 0] [--chunk K >= 1] OUTDIR'
    end subroutine parse_arguments

    ! Open path's temporary file and write the header (rank 0).
    subroutine open_csv(path, unit)
        character(len=*), intent(in) :: path
        integer, intent(out) :: unit
        open (newunit=unit, file=path // '.tmp', status='replace', action='write', iostat=ios)
        if (ios /= 0) call give_up('cannot write ' // path // '.tmp')
        write (unit, '(a)') csv_header()
    end subroutine open_csv

    ! Close the temporary file and rename it to path.
    subroutine close_csv(path, unit)
        character(len=*), intent(in) :: path
        integer, intent(in) :: unit
        close (unit)
        if (.not. rename_file(path // '.tmp', path)) call give_up('cannot rename ' // path // '.tmp')
    end subroutine close_csv

    ! A chunk's samples first, ..., first + cnt - 1, in order (each checked
    ! to be the sample expected there).
    subroutine take_chunk(kk, rr, mm, first, cnt)
        integer(int64), intent(in) :: first, cnt
        integer(int64), intent(in) :: kk(nk, *)
        real(real64), intent(in) :: rr(nr, *)
        character(len=ml), intent(in) :: mm(*)
        integer(int64) :: s
        do s = 1, cnt
            if (kk(k_index, s) /= first + s - 1) then
                print '(a, i0, a)', 'mpi_tube_search: sample ', first + s - 1, ' is missing from the gathered records'
                call MPI_Abort(MPI_COMM_WORLD, 1)
            end if
            call take_row(kk(:, s), rr(:, s), mm(s))
        end do
    end subroutine take_chunk

    ! One sample, in sample order: its row in samples.csv (and hits.csv if
    ! confirmed), and the report's counts.
    subroutine take_row(kk, rr, mm)
        integer(int64), intent(in) :: kk(nk)
        real(real64), intent(in) :: rr(nr)
        character(len=ml), intent(in) :: mm
        character(len=:), allocatable :: row
        row = csv_row(kk, rr, mm)
        write (u_all, '(a)') row
        if (is_hit(kk)) write (u_hits, '(a)') row
        counts(kk(k_class)) = counts(kk(k_class)) + 1
        if (kk(k_failed) /= 0) then
            failed = failed + 1
            return
        end if
        if (kk(k_coarse_status) < 0) stopped = stopped + 1
        coarse_rev = coarse_rev + kk(k_coarse_rev)
        coarse_dip = coarse_dip + kk(k_coarse_dip)
        hits_rev = hits_rev + kk(k_conf_rev)
        hits_dip = hits_dip + kk(k_conf_dip)
        if (kk(k_fine_status) < 0) fine_failed = fine_failed + 1
    end subroutine take_row

    subroutine give_up(text)
        character(len=*), intent(in) :: text
        print '(a)', 'mpi_tube_search: ' // text
        call MPI_Abort(MPI_COMM_WORLD, 1)
    end subroutine give_up
end program mpi_tube_search
