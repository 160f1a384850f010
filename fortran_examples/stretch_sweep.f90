! Torsionally relaxed stretching of a DNA-like thick tube from Fortran
! (physics.md 1.5): orthotropic Saint Venant-Kirchhoff wall of mid radius
! 1 nm and thickness 0.4 nm (A = 0.8, B = 1.2 nm), helix angle 60 degrees at
! the mid radius (tau0 = tan(60 deg)/R), in-surface constants of the thin-wall
! DNA fit at nu12 = 0.3 (E1 = 467.2, E2 = 516.2, G12 = 139.8 pN/nm^2; see
! rodkit::tube::dna), completed transversely isotropically (E3 = E2,
! nu13 = nu23 = nu12, G13 = G12, G23 = E2/(2(1 + nu23))).
! Zero torque and pressure, stretch 1 -> 1.05 in 26 steps; a progress
! callback prints every 5th step. Usage: f_stretch_sweep [--values] [csv path].
! Prints a short report (--values: also "name = value" lines and a table);
! with a path, rodkit writes the sweep as CSV (rodkit_tube_sweep_write_csv).
module sweep_progress
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_ptr, c_associated
    use rodkit, only: rodkit_progress
    implicit none
    ! --values (first argument): also every result as a "name = value" line
    ! (the channel rodkit's tests read), the progress and a table.
    logical :: values = .false.
contains
    function on_progress(progress, user_data) result(stop_now) bind(c)
        type(rodkit_progress), intent(in) :: progress
        type(c_ptr), value :: user_data
        integer(c_int32_t) :: stop_now
        if (values .and. mod(progress%done, 5_8) == 0) print '(a, i0, a, i0)', '# progress ', progress%done, '/', progress%total
        stop_now = 0
        if (c_associated(user_data)) stop_now = 0 ! user_data is unused here
    end function on_progress
end module sweep_progress

program stretch_sweep
    use, intrinsic :: iso_c_binding
    use rodkit
    use sweep_progress
    implicit none
    integer, parameter :: n = 26
    type(rodkit_tube_spec) :: spec
    type(rodkit_tube_loading) :: loadings(n)
    type(rodkit_tube_state) :: states(n)
    type(c_ptr) :: tube
    integer(c_int32_t) :: status
    integer(c_int64_t) :: completed
    real(c_double), parameter :: pi = acos(-1.0_c_double)
    integer :: i, first
    character(len=1024) :: csv_path
    character(len=16) :: flag

    first = 1
    if (command_argument_count() >= 1) then
        call get_command_argument(1, flag)
        values = flag == '--values'
        if (values) first = 2
    end if
    csv_path = ''
    if (command_argument_count() >= first) call get_command_argument(first, csv_path)

    status = rodkit_tube_spec_default(spec)
    spec%inner_radius = 0.8_c_double
    spec%outer_radius = 1.2_c_double
    spec%material%law = RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF
    spec%material%intrinsic_twist = tan(pi / 3.0_c_double)
    spec%material%e1 = 467.2_c_double
    spec%material%e2 = 516.2_c_double
    spec%material%e3 = 516.2_c_double
    spec%material%nu12 = 0.3_c_double
    spec%material%nu13 = 0.3_c_double
    spec%material%nu23 = 0.3_c_double
    spec%material%g12 = 139.8_c_double
    spec%material%g13 = 139.8_c_double
    spec%material%g23 = 516.2_c_double / (2.0_c_double * 1.3_c_double)
    spec%model = RODKIT_TUBE_MODEL_THICK
    spec%rel_tol = 1.0e-10_c_double

    status = rodkit_tube_new(spec, tube)
    if (status < 0) then
        print '(a)', 'rodkit_tube_new failed: ' // rodkit_last_error()
        error stop 1
    end if

    do i = 1, n
        status = rodkit_tube_loading_default(loadings(i))
        loadings(i)%axial_control = RODKIT_AXIAL_CONTROL_STRETCH
        loadings(i)%axial = 1.0_c_double + 0.002_c_double * real(i - 1, c_double)
        loadings(i)%torsion_control = RODKIT_TORSION_CONTROL_TORQUE
        loadings(i)%torsion = 0.0_c_double
    end do

    status = rodkit_tube_sweep(tube, loadings, int(n, c_int64_t), states, c_funloc(on_progress), c_null_ptr, completed)
    if (status < 0) then
        print '(a)', 'rodkit_tube_sweep failed: ' // rodkit_last_error()
        call rodkit_tube_free(tube)
        error stop 1
    end if

    if (values) print '(a, a)', '# rodkit ', RODKIT_VERSION_STRING // ': torsion-free stretching of a DNA-like thick tube (nm, pN)'
    if (values) print '(a, i0)', 'states = ', completed
    if (values) print '(a, es25.17e3)', 'stretch = ', states(n)%stretch
    if (values) print '(a, es25.17e3)', 'twist = ', states(n)%twist
    if (values) print '(a, es25.17e3)', 'applied_force = ', states(n)%applied_force
    if (values) print '(a, es25.17e3)', 'outer_radius = ', states(n)%deformed_outer_radius
    if (values) print '(a, es25.17e3)', 'torque = ', states(n)%torque
    if (values) print '(a)', '#  stretch    twist (deg/nm)   force (pN)   outer radius (nm)'
    do i = 1, n, 5
        if (values) print '(a, f8.4, f14.6, f13.4, f14.6)', '# ', states(i)%stretch, states(i)%twist * 180.0_c_double / pi, &
            states(i)%applied_force, states(i)%deformed_outer_radius
    end do
    print '(a)', 'A DNA-like thick tube (orthotropic SVK wall, A = 0.8 nm, B = 1.2 nm, helix 60 deg) stretched at zero torque'
    print '(a, f5.3, a, f0.2, a, f7.5, a, f7.5, a)', '  at stretch ', states(n)%stretch, ': force ', &
        states(n)%applied_force, ' pN, twist ', states(n)%twist * 180.0_c_double / pi, ' deg/nm (overwinds), outer radius ', &
        states(n)%deformed_outer_radius, ' nm'
    ! rodkit writes the sweep, loadings and states, as CSV when a path is given.
    if (len_trim(csv_path) > 0) then
        status = rodkit_tube_sweep_write_csv(loadings, states, completed, 'nm' // c_null_char, 'pN' // c_null_char, &
            trim(csv_path) // c_null_char)
        if (status < 0) then
            print '(a)', 'rodkit_tube_sweep_write_csv failed: ' // rodkit_last_error()
            error stop 1
        end if
        print '(a, i0, a)', '  sweep (', completed, ' states, CSV): ' // trim(csv_path)
    end if
    call rodkit_tube_free(tube)
end program stretch_sweep
