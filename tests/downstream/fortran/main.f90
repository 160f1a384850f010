! A downstream Fortran program, built against an installed rodkit by CMake
! (find_package(rodkit), target rodkit::fortran: the compiled module
! rodkit.mod and librodkit_fortran.a, linked with librodkit) and by
! pkg-config (rodkit-fortran.pc). It checks the library's version against
! the module's constants and the helix angle atan(tau0 R) of a thin
! tube's reinforcement against its closed form.
program downstream
    use, intrinsic :: iso_c_binding, only: c_double, c_int32_t
    use rodkit
    implicit none
    type(rodkit_thin_tube_spec) :: spec
    integer(c_int32_t) :: major, minor, patch, status
    real(c_double) :: alpha

    status = rodkit_version(major, minor, patch)
    if (status /= 0 .or. major /= RODKIT_VERSION_MAJOR .or. minor /= RODKIT_VERSION_MINOR &
        .or. patch /= RODKIT_VERSION_PATCH .or. rodkit_library_abi_version() /= RODKIT_ABI_VERSION) then
        print '(a)', 'version mismatch between the library and the module'
        error stop 1
    end if
    status = rodkit_thin_tube_spec_default(spec)
    spec%mid_radius = 2.0_c_double
    spec%thickness = 0.05_c_double
    spec%intrinsic_twist = 0.25_c_double
    spec%e1 = 200.0_c_double
    spec%e2 = 100.0_c_double
    spec%nu12 = 0.3_c_double
    spec%g12 = 40.0_c_double
    status = rodkit_thin_tube_helix_angle(spec, alpha)
    if (status /= 0) then
        print '(a)', rodkit_last_error()
        error stop 1
    end if
    print '(a, i0, a, i0, a, es23.15, a, es23.15)', 'rodkit ', major, '.', minor, ': helix angle ', alpha, &
        ', atan(0.5) = ', atan(0.5_c_double)
    if (abs(alpha - atan(0.5_c_double)) > 1e-15_c_double) error stop 1
end program downstream
