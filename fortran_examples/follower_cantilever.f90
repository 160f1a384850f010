! The follower-load cantilever from Fortran (physics.md 2.6): a Cosserat rod
! (K_b = 1, C = 1/1.3, GA = 1e4, EA = 2.6e4, L = 1; Gauss-Legendre 4 stages,
! 8 elements) clamped at s = 0, loaded at the tip by a force Lambda*(1, 0, 0)
! in the body frame (perpendicular to the tip tangent), continued by the ANM
! (order 20, eps 1e-10, residual 1e-10) from alpha = Lambda L^2/K_b = 0 to 1,
! 2, 5 and 10, each a target reached by resuming the previous branch. A
! progress callback counts the points. Prints "name = value" lines and a
! table; the tip curls past 90 degrees and beyond. Then the same branch
! once more in a single run with dense output: 20 loads alpha = 0.5, 1, ...,
! 10 delivered from the ANM's series (Pade approximants on), each within the
! residual tolerance; rodkit writes the shapes at alpha = 1, 2, 5, 10 as VTK
! polydata for ParaView (rodkit_branch_write_samples_vtk) and all 20 samples
! as CSV (rodkit_branch_write_samples_csv) when their paths are given.
! Usage: f_follower_cantilever [--values] [vtk path] [csv path]
! Prints a short report (--values: also "name = value" lines and tables).
module follower_progress
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_ptr, c_f_pointer
    use rodkit, only: rodkit_branch_progress
    implicit none
contains
    function count_points(progress, user_data) result(stop_now) bind(c)
        type(rodkit_branch_progress), intent(in) :: progress
        type(c_ptr), value :: user_data
        integer(c_int32_t) :: stop_now
        integer(c_int64_t), pointer :: calls
        call c_f_pointer(user_data, calls)
        calls = calls + 1
        stop_now = 0
        if (progress%residual > 1.0d-6) stop_now = 1 ! never: every point meets the tolerance
    end function count_points
end module follower_progress

program follower_cantilever
    use, intrinsic :: iso_c_binding
    use rodkit
    use follower_progress
    implicit none
    type(rodkit_rod_spec) :: spec
    type(rodkit_continuation_options) :: opts
    type(rodkit_branch_info) :: info
    type(rodkit_branch_record), allocatable :: rec(:)
    type(c_ptr) :: rod, branch, next
    integer(c_int32_t) :: status
    integer(c_int64_t) :: n, count, steps, factorisations
    integer(c_int64_t), target :: calls
    real(c_double), allocatable :: x0(:)
    real(c_double), parameter :: alphas(4) = [1.0_c_double, 2.0_c_double, 5.0_c_double, 10.0_c_double]
    real(c_double), parameter :: pi = acos(-1.0_c_double)
    character(len=2) :: tag
    character(len=1024) :: vtk_path, csv_path
    character(len=16) :: flag
    logical :: values
    integer :: k, i, first
    real(c_double), allocatable, target :: loads(:)
    type(rodkit_branch_record), allocatable :: dense(:)
    type(rodkit_record_error), allocatable :: estimates(:)
    type(c_ptr) :: fine_rod
    integer(c_int64_t) :: n_fine
    real(c_double), allocatable :: x_fine(:)
    real(c_double) :: tip_r(3), tip_q(4), tip_f(3), tip_m(3), tip_rot(3)

    ! --values (first argument): also every result as a "name = value" line
    ! (the channel rodkit's tests read) and the tables; else a short report.
    values = .false.
    first = 1
    if (command_argument_count() >= 1) then
        call get_command_argument(1, flag)
        values = flag == '--values'
        if (values) first = 2
    end if
    vtk_path = ''
    csv_path = ''
    if (command_argument_count() >= first) call get_command_argument(first, vtk_path)
    if (command_argument_count() >= first + 1) call get_command_argument(first + 1, csv_path)

    status = rodkit_rod_spec_default(spec)
    spec%length = 1.0_c_double
    spec%bending1 = 1.0_c_double
    spec%bending2 = 1.0_c_double
    spec%twist = 1.0_c_double / 1.3_c_double
    spec%shear1 = 1.0e4_c_double
    spec%shear2 = 1.0e4_c_double
    spec%stretch = 2.6e4_c_double
    spec%tip_force_frame = RODKIT_LOAD_FRAME_FOLLOWER
    spec%tip_force_x = 1.0_c_double
    spec%scheme = RODKIT_ROD_SCHEME_GAUSS
    spec%stages = 4
    spec%elements = 8
    status = rodkit_rod_new(spec, rod)
    if (status < 0) then
        print '(a)', 'rodkit_rod_new failed: ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_rod_unknowns(rod, n)
    allocate(x0(n))
    status = rodkit_rod_straight_state(rod, x0, n)

    status = rodkit_continuation_options_default(opts)
    opts%method = RODKIT_CONTINUATION_METHOD_ANM
    opts%anm_order = 20
    opts%anm_epsilon = 1.0e-10_c_double
    opts%residual_tol = 1.0e-10_c_double
    opts%max_step = 2.0_c_double
    calls = 0
    steps = 0
    factorisations = 0
    if (values) print '(a)', '# rodkit ' // RODKIT_VERSION_STRING // ': follower cantilever, ANM (P = 20, eps = 1e-10)'
    if (values) print '(a)', '#  alpha      tip x         tip z     tip rotation(deg)  steps'
    branch = c_null_ptr
    do k = 1, 4
        opts%target_lambda = alphas(k)
        if (k == 1) then
            status = rodkit_rod_continue(rod, x0, n, 0.0_c_double, opts, c_funloc(count_points), c_loc(calls), next)
        else
            status = rodkit_branch_resume(rod, branch, opts, c_funloc(count_points), c_loc(calls), next)
            call rodkit_branch_free(branch)
        end if
        if (status /= RODKIT_STATUS_OK) then
            print '(a, i0, a)', 'continuation to the target failed (status ', status, '): ' // rodkit_last_error()
            error stop 1
        end if
        branch = next
        status = rodkit_branch_summary(branch, info)
        steps = steps + info%steps
        factorisations = factorisations + info%factorisations
        allocate(rec(info%records))
        status = rodkit_branch_records(branch, rec, info%records, count)
        write(tag, '(i0)') nint(alphas(k))
        if (values) print '(f7.2, 2f14.9, f14.4, i7)', rec(count)%lambda, rec(count)%tip_x, rec(count)%tip_z, &
            rec(count)%tip_rotation * 180.0_c_double / pi, info%steps
        if (values) print '(a, es24.16)', 'tip_x_' // trim(tag) // ' = ', rec(count)%tip_x
        if (values) print '(a, es24.16)', 'tip_y_' // trim(tag) // ' = ', rec(count)%tip_y
        if (values) print '(a, es24.16)', 'tip_z_' // trim(tag) // ' = ', rec(count)%tip_z
        deallocate(rec)
    end do
    if (values) print '(a, i0)', 'steps = ', steps
    if (values) print '(a, i0)', 'factorisations = ', factorisations
    if (values) print '(a, i0)', 'callback_calls = ', calls
    call rodkit_branch_free(branch)

    ! Dense output in one run: 20 loads from the series (Pade on).
    allocate(loads(20))
    loads = [(0.5_c_double * i, i = 1, 20)]
    opts%target_lambda = 10.0_c_double
    opts%max_step = 10.0_c_double
    opts%anm_pade = 1
    opts%samples = c_loc(loads)
    opts%sample_count = size(loads, kind=c_int64_t)
    status = rodkit_rod_continue(rod, x0, n, 0.0_c_double, opts, c_null_funptr, c_null_ptr, branch)
    if (status /= RODKIT_STATUS_OK) then
        print '(a, i0, a)', 'dense run failed (status ', status, '): ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_branch_summary(branch, info)
    allocate(dense(info%samples))
    status = rodkit_branch_samples(branch, dense, info%samples, count)
    if (values) print '(a)', '# dense output, one run (ANM P = 20, eps = 1e-10, Pade):'
    if (values) print '(a)', '#  alpha      tip x         tip z       residual'
    do i = 1, int(count)
        if (values) print '(f7.2, 2f14.9, es12.2)', dense(i)%lambda, dense(i)%tip_x, dense(i)%tip_z, dense(i)%residual
    end do
    if (values) print '(a, i0)', 'dense_samples = ', count
    if (values) print '(a, i0)', 'dense_missed = ', info%missed_samples
    if (values) print '(a, i0)', 'dense_steps = ', info%steps
    if (values) print '(a, i0)', 'dense_factorisations = ', info%factorisations
    if (values) print '(a, es24.16)', 'dense_tip_x_5 = ', dense(10)%tip_x
    if (values) print '(a, es24.16)', 'dense_tip_z_5 = ', dense(10)%tip_z
    if (values) print '(a, es24.16)', 'dense_tip_x_10 = ', dense(20)%tip_x
    if (values) print '(a, es24.16)', 'dense_tip_z_10 = ', dense(20)%tip_z
    if (values) print '(a, es24.16)', 'dense_max_residual = ', maxval(dense(:)%residual)
    ! rodkit writes the shapes at alpha = 1, 2, 5, 10 (samples 2, 4, 10, 20;
    ! 0-based indices) as VTK, cell data lambda, and every sample as CSV.
    if (len_trim(vtk_path) > 0) then
        status = rodkit_branch_write_samples_vtk(branch, rod, [1_c_int64_t, 3_c_int64_t, 9_c_int64_t, 19_c_int64_t], &
            4_c_int64_t, trim(vtk_path) // c_null_char)
        if (status < 0) then
            print '(a)', 'rodkit_branch_write_samples_vtk failed: ' // rodkit_last_error()
            error stop 1
        end if
    end if
    if (len_trim(csv_path) > 0) then
        status = rodkit_branch_write_samples_csv(branch, rod, trim(csv_path) // c_null_char)
        if (status < 0) then
            print '(a)', 'rodkit_branch_write_samples_csv failed: ' // rodkit_last_error()
            error stop 1
        end if
    end if
    print '(a)', 'A cantilever under a follower tip force (K_b = 1, L = 1, 8 elements), continued by the ANM to alpha = 10'
    print '(a, i0, a, i0, a)', '  ', count, ' loads alpha = 0.5 ... 10 from one run of ', info%steps, &
        ' steps (Pade), each within the residual tolerance 1e-10'
    print '(a, f9.6, a, f9.6, a, f6.2, a)', '  tip at alpha = 10: (x, z) = (', dense(20)%tip_x, ', ', dense(20)%tip_z, &
        '), tip rotation ', dense(20)%tip_rotation * 180.0_c_double / pi, ' deg'
    if (len_trim(vtk_path) > 0) print '(a)', '  shapes at alpha = 1, 2, 5, 10 (VTK, for ParaView): ' // trim(vtk_path)
    if (len_trim(csv_path) > 0) print '(a, i0, a)', '  samples (', count, ', CSV): ' // trim(csv_path)
    call rodkit_branch_free(branch)

    ! To a tolerance: rodkit chooses the elements (from this rod's 8) so
    ! that every record's estimated error is below 1e-6, and says so.
    status = rodkit_continuation_options_default(opts)
    opts%target_lambda = 10.0_c_double
    opts%residual_tol = 1.0e-12_c_double
    status = rodkit_rod_continue_to_tolerance(rod, 1.0e-6_c_double, 0.0_c_double, opts, c_null_funptr, &
        c_null_ptr, fine_rod, branch)
    if (status /= RODKIT_STATUS_OK) then
        print '(a, i0, a)', 'to a tolerance failed (status ', status, '): ' // rodkit_last_error()
        error stop 1
    end if
    status = rodkit_rod_unknowns(fine_rod, n_fine)
    status = rodkit_branch_summary(branch, info)
    if (allocated(rec)) deallocate(rec)
    allocate(rec(info%records), estimates(info%records), x_fine(n_fine))
    status = rodkit_branch_records(branch, rec, info%records, count)
    status = rodkit_branch_error_estimates(branch, fine_rod, estimates, info%records, count)
    ! The tip frame at α = 10 from the last state, through the accessor.
    status = rodkit_branch_state(branch, count - 1, x_fine, n_fine)
    status = rodkit_rod_node_state(fine_rod, x_fine, n_fine, (n_fine / 13 - 1) / 5, tip_r, tip_q, tip_f, tip_m)
    if (values) print '(a)', '# to a tolerance of 1e-6 (ANM defaults): elements chosen, worst estimate, tip at alpha = 10'
    if (values) print '(a, i0)', 'tolerance_elements = ', (n_fine / 13 - 1) / 5
    if (values) print '(a, es24.16)', 'tolerance_worst_estimate = ', maxval(estimates(:)%scaled)
    if (values) print '(a, i0)', 'tolerance_estimated = ', sum(estimates(:)%estimated)
    if (values) print '(a, i0)', 'tolerance_records = ', count
    if (values) print '(a, es24.16)', 'tolerance_tip_x_10 = ', rec(count)%tip_x
    if (values) print '(a, es24.16)', 'tolerance_tip_z_10 = ', rec(count)%tip_z
    if (values) print '(a, es24.16)', 'tolerance_tip_q0_10 = ', tip_q(1)
    if (values) print '(a, es24.16)', 'tolerance_tip_q2_10 = ', tip_q(3)
    if (values) print '(a, es24.16)', 'tolerance_tip_rx_10 = ', tip_r(1)
    ! The tip's signed rotation (the rotation vector of its frame): about
    ! +e2 for this rod bent towards +e1, the shortest rotation (|angle| <= pi).
    status = rodkit_rod_node_rotation(fine_rod, x_fine, n_fine, (n_fine / 13 - 1) / 5, tip_rot)
    if (values) print '(a, es24.16)', 'tolerance_tip_rotation_e2_10 = ', tip_rot(2)
    print '(a, i0, a, es9.2, a)', '  to a tolerance of 1e-6: rodkit chose ', (n_fine / 13 - 1) / 5, &
        ' elements (worst estimated error ', maxval(estimates(:)%scaled), ')'
    call rodkit_branch_free(branch)
    call rodkit_rod_free(fine_rod)
    call rodkit_rod_free(rod)
end program follower_cantilever
