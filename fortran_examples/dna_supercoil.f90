! DNA supercoiling from Fortran (physics.md 3, issue 5): the DNA scene
! (300 bp, 1 pN, 0.1 M salt, continuum line charge, 40 elements, 20 steps)
! continued in the end rotation through its first buckling point, then its
! last point re-solved with discrete base-pair charges (the thesis's
! comparison) by Newton-Krylov and by the direct sparse Newton. Exercises
! the supercoil handle, its accessors and rodkit_supercoil_solve_point
! through the module's bind(c) types. Prints "name = value" lines.
program dna_supercoil
    use, intrinsic :: iso_c_binding
    use rodkit
    implicit none
    type(rodkit_dna_supercoil_spec) :: spec
    type(rodkit_supercoil_info) :: info
    type(rodkit_supercoil_point), allocatable :: points(:)
    type(rodkit_equilibrium_spec) :: es
    type(rodkit_equilibrium) :: nk, direct
    real(c_double), allocatable :: xyz(:, :)
    type(c_ptr) :: run
    integer(c_int64_t) :: count, last
    integer(c_int32_t) :: status

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
    call rodkit_supercoil_free(run)

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
