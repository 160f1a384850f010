! DNA supercoiling from Fortran (physics.md 3, issue 5): the DNA scene
! (300 bp, 1 pN, 0.1 M salt, continuum line charge, 40 elements, 20 steps)
! continued in the end rotation through its first buckling point, then its
! last point re-solved with discrete base-pair charges (the thesis's
! comparison) by Newton-Krylov and by the direct sparse Newton. Exercises
! the supercoil handle, its accessors and rodkit_supercoil_solve_point
! through the module's bind(c) types. Then the same run stopped by a
! Fortran progress callback after 15 points (RODKIT_STATUS_INFO_CANCELLED,
! the path so far) and resumed to its end (issue 18), after the curve's
! summary and energies (rodkit_supercoil_curve_summary/_points). Prints
! "name = value" lines.
module supercoil_progress
    use, intrinsic :: iso_c_binding
    use rodkit, only: rodkit_branch_progress
    implicit none
contains
    ! state(1) counts the points told, state(2): stop after that many (0:
    ! never), state(3) receives the branch of the last point told, state(4)
    ! drops to 0 if progress%points ever differs from the count (told out of
    ! order or twice).
    function stop_after(progress, user_data) result(stop_now) bind(c)
        type(rodkit_branch_progress), intent(in) :: progress
        type(c_ptr), value :: user_data
        integer(c_int32_t) :: stop_now
        integer(c_int64_t), pointer :: state(:)
        call c_f_pointer(user_data, state, [4])
        state(1) = state(1) + 1
        state(3) = progress%branch
        if (progress%points /= state(1)) state(4) = 0
        stop_now = 0
        if (state(1) == state(2)) stop_now = 1
    end function stop_after
end module supercoil_progress

program dna_supercoil
    use, intrinsic :: iso_c_binding
    use rodkit
    use supercoil_progress
    implicit none
    type(rodkit_dna_supercoil_spec) :: spec
    type(rodkit_supercoil_info) :: info
    type(rodkit_supercoil_point), allocatable :: points(:)
    type(rodkit_equilibrium_spec) :: es
    type(rodkit_equilibrium) :: nk, direct
    real(c_double), allocatable :: xyz(:, :)
    type(c_ptr) :: run
    integer(c_int64_t) :: count, last
    integer(c_int32_t) :: status, stop
    integer(c_int64_t), target :: state(4)
    type(c_ptr) :: stopped
    type(rodkit_supercoil_curve_info) :: curve
    type(rodkit_supercoil_curve_point), allocatable :: curve_points(:)

    status = rodkit_dna_supercoil_spec_default(spec)
    call check(status, 'rodkit_dna_supercoil_spec_default')
    spec%base_pairs = 300
    spec%elements = 40
    spec%max_steps = 20
    status = rodkit_dna_supercoil_run(spec, run)
    call check(status, 'rodkit_dna_supercoil_run')
    status = rodkit_supercoil_summary(run, info)
    call check(status, 'rodkit_supercoil_summary')
    allocate (points(info%points), xyz(3, info%nodes))
    status = rodkit_supercoil_points(run, points, info%points, count)
    call check(status, 'rodkit_supercoil_points')
    last = count - 1

    status = rodkit_equilibrium_spec_default(es)
    call check(status, 'rodkit_equilibrium_spec_default')
    es%discrete_base_pairs = 1
    es%solver = RODKIT_EQUILIBRIUM_SOLVER_NEWTON_KRYLOV
    status = rodkit_supercoil_solve_point(run, last, es, nk, xyz, 3_c_int64_t, info%nodes)
    call check(status, 'rodkit_supercoil_solve_point (Newton-Krylov)')
    es%solver = RODKIT_EQUILIBRIUM_SOLVER_DIRECT
    status = rodkit_supercoil_solve_point(run, last, es, direct, xyz, 3_c_int64_t, info%nodes)
    call check(status, 'rodkit_supercoil_solve_point (direct)')

    print '(a)', '# rodkit ' // RODKIT_VERSION_STRING // ': DNA supercoiling, 300 bp, 1 pN, 0.1 M, 40 elements, 20 steps'
    print '(a, i0)', 'points = ', count
    print '(a, es24.16)', 'buckling_turns = ', info%buckling_turns
    print '(a, es24.16)', 'buckling_torque_pN_nm = ', info%buckling_torque
    print '(a, es24.16)', 'last_turns = ', points(count)%turns
    print '(a, es24.16)', 'last_extension_nm = ', points(count)%extension
    print '(a, es24.16)', 'last_torque_pN_nm = ', points(count)%torque
    print '(a, es24.16)', 'base_pair_torque_pN_nm = ', nk%torque
    print '(a, es24.16)', 'base_pair_extension_nm = ', nk%extension
    print '(a, es24.16)', 'base_pair_shift_nm = ', nk%shift
    print '(a, es24.16)', 'direct_torque_pN_nm = ', direct%torque
    print '(a, es24.16)', 'direct_tip_z_nm = ', xyz(3, info%nodes)
    print '(a, i0)', 'newton_krylov_iterations = ', nk%newton_iterations
    print '(a, i0)', 'gmres_iterations = ', nk%linear_iterations
    print '(a, i0)', 'preconditioner_band = ', nk%preconditioner_band

    ! The equilibrium curve's summary and points (issue 18, deliverables 4-5).
    status = rodkit_supercoil_curve_summary(run, curve)
    call check(status, 'rodkit_supercoil_curve_summary')
    allocate (curve_points(info%points))
    status = rodkit_supercoil_curve_points(run, curve_points, info%points, count)
    call check(status, 'rodkit_supercoil_curve_points')
    print '(a, i0)', 'curve_instability_finding = ', curve%instability_finding
    print '(a, es24.16)', 'curve_instability_turns = ', curve%instability_turns
    print '(a, i0)', 'curve_coexistence_finding = ', curve%coexistence_finding
    print '(a, i0)', 'curve_superhelix_finding = ', curve%superhelix_finding
    print '(a, i0)', 'curve_points = ', count
    print '(a, es24.16)', 'curve_last_energy_pN_nm = ', curve_points(count)%energy
    print '(a, i0)', 'curve_last_branch = ', curve_points(count)%branch
    call rodkit_supercoil_free(run)

    ! The same run, stopped by the callback after 15 points, then resumed.
    state = [0_c_int64_t, 15_c_int64_t, -1_c_int64_t, 1_c_int64_t]
    status = rodkit_dna_supercoil_run_with(spec, c_funloc(stop_after), c_loc(state), stopped)
    call check(status, 'rodkit_dna_supercoil_run_with')
    print '(a, i0)', 'cancel_status = ', status
    status = rodkit_supercoil_stop(stopped, stop)
    call check(status, 'rodkit_supercoil_stop')
    print '(a, i0)', 'cancelled_stop = ', stop
    status = rodkit_supercoil_summary(stopped, info)
    call check(status, 'rodkit_supercoil_summary')
    print '(a, i0)', 'cancelled_points = ', info%points
    print '(a, i0)', 'cancelled_branch = ', state(3)
    state(2) = 0
    status = rodkit_supercoil_resume(stopped, c_funloc(stop_after), c_loc(state))
    call check(status, 'rodkit_supercoil_resume')
    status = rodkit_supercoil_stop(stopped, stop)
    call check(status, 'rodkit_supercoil_stop')
    print '(a, i0)', 'resumed_stop = ', stop
    status = rodkit_supercoil_summary(stopped, info)
    call check(status, 'rodkit_supercoil_summary')
    deallocate (points)
    allocate (points(info%points))
    status = rodkit_supercoil_points(stopped, points, info%points, count)
    call check(status, 'rodkit_supercoil_points')
    print '(a, i0)', 'resumed_points = ', count
    print '(a, i0)', 'told_points = ', state(1)
    print '(a, i0)', 'told_in_order = ', state(4)
    print '(a, es24.16)', 'resumed_last_extension_nm = ', points(count)%extension
    print '(a, es24.16)', 'resumed_last_torque_pN_nm = ', points(count)%torque
    call rodkit_supercoil_free(stopped)

contains
    subroutine check(status, what)
        integer(c_int32_t), intent(in) :: status
        character(*), intent(in) :: what
        if (status < 0) then
            print '(a)', what // ' failed: ' // rodkit_last_error()
            error stop 1
        end if
    end subroutine check
end program dna_supercoil
