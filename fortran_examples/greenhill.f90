! Greenhill's twisted rod from Fortran (issue 19): a Kirchhoff rod (K_b = C
! = L = 1, Gauss-Legendre 4 stages) clamped at both ends, its far end
! turned by phi about the axis (rotation control: Lambda = sin(phi/2),
! which takes every value again each turn). The straight branch is
! followed by Newton continuation to phi = 25 exactly
! (rodkit_rod_set_target_rotation), with bifurcation detection, and the
! elements are chosen by rodkit for a tolerance of 1e-6
! (rodkit_rod_continue_to_tolerance from 4 elements): every record's
! estimate and every critical twist's meet it. Each located point is
! printed with the record it follows, its multiplicity (2: the rod is
! isotropic), its evidence, the estimate of its critical phi
! (rodkit_branch_bifurcation_errors) and the closed form theta_k
! (tan(theta/2) = theta/2) with the true error. Prints "name = value"
! lines and a table.
program greenhill
    use, intrinsic :: iso_c_binding
    use rodkit
    implicit none
    type(rodkit_rod_spec) :: spec
    type(rodkit_continuation_options) :: opts
    type(rodkit_branch_info) :: info
    type(rodkit_branch_record), allocatable :: rec(:)
    type(rodkit_bifurcation_point) :: points(8)
    type(rodkit_bifurcation_error) :: errors(8)
    type(c_ptr) :: rod, fine_rod, branch
    integer(c_int32_t) :: status
    integer(c_int64_t) :: n, count, n_points, elements
    real(c_double), parameter :: tolerance = 1.0e-6_c_double, phi_end = 25.0_c_double
    real(c_double) :: theta, worst
    character(len=2) :: tag
    integer :: k
    logical :: values
    character(len=16) :: flag

    ! --values (first argument): also every result as a "name = value" line
    ! (the channel rodkit's tests read) and the tables; else a short report.
    values = .false.
    if (command_argument_count() >= 1) then
        call get_command_argument(1, flag)
        values = flag == '--values'
    end if

    status = rodkit_rod_spec_default(spec)
    spec%length = 1.0_c_double
    spec%bending1 = 1.0_c_double
    spec%bending2 = 1.0_c_double
    spec%twist = 1.0_c_double
    spec%kirchhoff = 1
    spec%supports = RODKIT_ROD_SUPPORTS_TWISTED
    spec%scheme = RODKIT_ROD_SCHEME_GAUSS
    spec%stages = 4
    spec%elements = 4
    status = rodkit_rod_new(spec, rod)
    if (status < 0) then
        print '(a)', 'rodkit_rod_new failed: ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_rod_set_target_rotation(rod, phi_end)
    if (status /= RODKIT_STATUS_OK) then
        print '(a)', 'rodkit_rod_set_target_rotation failed: ' // rodkit_last_error()
        error stop 1
    end if

    status = rodkit_continuation_options_default(opts)
    opts%method = RODKIT_CONTINUATION_METHOD_NEWTON
    opts%residual_tol = 1.0e-12_c_double
    opts%initial_step = 0.05_c_double
    opts%max_step = 1.0_c_double
    opts%max_steps = 2000
    opts%detect_bifurcations = 1
    opts%bifurcation_tol = 1.0e-9_c_double
    status = rodkit_rod_continue_to_tolerance(rod, tolerance, 0.0_c_double, opts, c_null_funptr, c_null_ptr, &
        fine_rod, branch)
    if (status /= RODKIT_STATUS_OK) then
        print '(a, i0, a)', 'continuation to the tolerance failed (status ', status, '): ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_rod_unknowns(fine_rod, n)
    elements = (n / 13 - 1) / 5 ! Gauss(4): 13 values at each node and 4 stages, and the end's cosine
    status = rodkit_branch_summary(branch, info)
    allocate(rec(info%records))
    status = rodkit_branch_records(branch, rec, info%records, count)
    status = rodkit_branch_bifurcation_points(branch, fine_rod, points, 8_c_int64_t, n_points)
    if (status /= RODKIT_STATUS_OK .or. n_points > 8) then
        print '(a)', 'rodkit_branch_bifurcation_points failed: ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_branch_bifurcation_errors(branch, fine_rod, errors, 8_c_int64_t, count)
    if (status /= RODKIT_STATUS_OK) then
        print '(a)', 'rodkit_branch_bifurcation_errors failed: ' // rodkit_last_error()
        error stop 1
    end if

    if (values) print '(a)', '# rodkit ' // RODKIT_VERSION_STRING // ': Greenhill''s rod turned to phi = 25, tolerance 1e-6'
    if (values) print '(a, i0, a, i0, a)', '# ', elements, ' elements chosen, ', info%records, ' records'
    if (values) print '(a)', '#  k  record  mult   critical phi      estimate       theta_k (closed form)   true error'
    worst = 0.0_c_double
    do k = 1, int(n_points)
        theta = greenhill_root(k)
        if (values) print '(i4, i8, i6, f17.10, es14.3, f17.10, es18.3)', k, points(k)%record, points(k)%multiplicity, &
            points(k)%end_rotation, errors(k)%end_rotation, theta, abs(points(k)%end_rotation - theta)
        write(tag, '(i0)') k
        if (values) print '(a, es24.16)', 'critical_phi_' // trim(tag) // ' = ', points(k)%end_rotation
        if (values) print '(a, es24.16)', 'critical_phi_estimate_' // trim(tag) // ' = ', errors(k)%end_rotation
        if (values) print '(a, i0)', 'critical_estimated_' // trim(tag) // ' = ', errors(k)%estimated
        if (values) print '(a, i0)', 'critical_record_' // trim(tag) // ' = ', points(k)%record
        if (values) print '(a, i0)', 'critical_multiplicity_' // trim(tag) // ' = ', points(k)%multiplicity
        worst = max(worst, errors(k)%scaled)
    end do
    if (values) print '(a, i0)', 'elements = ', elements
    if (values) print '(a, i0)', 'records = ', info%records
    if (values) print '(a, i0)', 'points = ', n_points
    if (values) print '(a, es24.16)', 'final_end_rotation = ', rec(info%records)%end_rotation
    if (values) print '(a, es24.16)', 'worst_critical_estimate = ', worst
    print '(a)', 'Greenhill''s problem: a Kirchhoff rod (K_b = C = 1, L = 1) turned to phi = 25 by rotation control'
    print '(a, i0, a, *(f11.6))', '  ', n_points, ' critical twists found at phi =', points(1:n_points)%end_rotation
    print '(a, *(f11.6))', '  closed form (tan(theta/2) = theta/2):', [(greenhill_root(k), k = 1, int(n_points))]
    print '(a, i0, a, es9.2, a)', '  ', elements, ' elements chosen by rodkit for 1e-6 (worst estimate ', worst, ')'
    deallocate(rec)
    call rodkit_branch_free(branch)
    call rodkit_rod_free(fine_rod)
    call rodkit_rod_free(rod)
contains
    ! The k-th root theta = 2x of tan x = x (x in (k pi, k pi + pi/2)),
    ! by Newton from just below the asymptote.
    function greenhill_root(k) result(theta)
        integer, intent(in) :: k
        real(c_double) :: theta, x
        integer :: i
        x = (real(k, c_double) + 0.5_c_double) * acos(-1.0_c_double) - 0.05_c_double
        do i = 1, 60
            x = x - (tan(x) - x) / (1.0_c_double / cos(x)**2 - 1.0_c_double)
        end do
        theta = 2.0_c_double * x
    end function greenhill_root
end program greenhill
