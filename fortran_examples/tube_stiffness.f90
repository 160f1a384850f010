! Thin-tube coupling stiffness from Fortran (physics.md 1.4): the Fortran twin
! of c_examples/tube_stiffness.c.
!
! Usage: tube_stiffness [input.nml]   (default: fortran_examples/dna_tube.nml,
! relative to the repository root). Reads the namelist
!     &tube mid_radius=..., thickness=..., intrinsic_twist=..., e1=..., e2=...,
!           nu12=..., g12=... /
! into a rodkit_thin_tube_spec, prints the inputs, the 3x3 coupling stiffness
! K, the condensed stretch-twist law and the free-tube response as
! "name = value" lines with the same names as the C driver (values with 18
! significant digits, so the test suite can compare them with the Rust and C
! results), then makes a deliberate bad call and prints "error_caught = 1"
! when rodkit reports it with the expected status and message.
! Any unexpected failure ends the program with ERROR STOP (nonzero exit).
!
! Build (from the repository root):
!   gfortran -std=f2008 -c include/rodkit.f90 -J build -o build/rodkit_mod.o
!   gfortran -std=f2008 -Ibuild fortran_examples/tube_stiffness.f90 build/rodkit_mod.o \
!       -Ltarget/release -lrodkit -Wl,-rpath,$PWD/target/release -o build/f_tube_stiffness
program tube_stiffness
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_double
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use rodkit
    implicit none

    character(len=*), parameter :: default_input = "fortran_examples/dna_tube.nml"
    character(len=*), parameter :: names(3) = [character(len=6) :: "strain", "twist", "hoop"]
    character(len=:), allocatable :: path
    integer(c_int32_t) :: major, minor, patch, abi, st
    type(rodkit_thin_tube_spec) :: spec, bad
    type(rodkit_free_tube_response) :: response
    real(c_double) :: alpha, k(3, 3), s(2, 2), rod(6, 6)
    real(c_double) :: mid_radius, thickness, intrinsic_twist, e1, e2, nu12, g12
    character(len=:), allocatable :: message
    character(len=256) :: iomsg
    integer :: i, j, n, unit, ios
    namelist /tube/ mid_radius, thickness, intrinsic_twist, e1, e2, nu12, g12

    ! Input path: first command-line argument, else the bundled DNA tube.
    if (command_argument_count() >= 1) then
        call get_command_argument(1, length=n)
        allocate(character(len=n) :: path)
        call get_command_argument(1, path)
    else
        path = default_input
    end if

    ! The library must be the one this module was written for.
    call check(rodkit_version(major, minor, patch), "rodkit_version")
    abi = rodkit_library_abi_version()
    if (major /= RODKIT_VERSION_MAJOR .or. abi /= RODKIT_ABI_VERSION) then
        write(error_unit, '(a,a,a,i0,a,i0,a,i0,a,i0,a,i0)') "module/library mismatch: module ", &
            RODKIT_VERSION_STRING, " ABI ", RODKIT_ABI_VERSION, ", library ", major, ".", minor, ".", &
            patch, " ABI ", abi
        error stop 1
    end if
    write(output_unit, '(a,i0,a,i0,a,i0,a,i0,a,a)') "# rodkit ", major, ".", minor, ".", patch, &
        " (ABI ", abi, "): thin-tube coupling stiffness from Fortran, input ", path

    ! Every field starts unset (NaN): a field missing from the namelist stays
    ! NaN and rodkit rejects it by name.
    call check(rodkit_thin_tube_spec_default(spec), "spec_default")
    mid_radius = spec%mid_radius
    thickness = spec%thickness
    intrinsic_twist = spec%intrinsic_twist
    e1 = spec%e1
    e2 = spec%e2
    nu12 = spec%nu12
    g12 = spec%g12
    open(newunit=unit, file=path, status="old", action="read", iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
        write(error_unit, '(a)') path // ": " // trim(iomsg)
        error stop 1
    end if
    read(unit, nml=tube, iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
        write(error_unit, '(a)') path // ": cannot read namelist &tube: " // trim(iomsg)
        error stop 1
    end if
    close(unit)
    spec%mid_radius = mid_radius
    spec%thickness = thickness
    spec%intrinsic_twist = intrinsic_twist
    spec%e1 = e1
    spec%e2 = e2
    spec%nu12 = nu12
    spec%g12 = g12

    call put("mid_radius", spec%mid_radius)
    call put("thickness", spec%thickness)
    call put("intrinsic_twist", spec%intrinsic_twist)
    call put("e1", spec%e1)
    call put("e2", spec%e2)
    call put("nu12", spec%nu12)
    call put("g12", spec%g12)

    call check(rodkit_thin_tube_helix_angle(spec, alpha), "helix_angle")
    ! Same operations, in the same order, as the C driver.
    call put("helix_angle_deg", (alpha * 180.0_c_double) / acos(-1.0_c_double))

    ! k(3, 3) is column-major with leading dimension 3: K(i, j) = k(i, j).
    call check(rodkit_thin_tube_coupling_stiffness(spec, k, 3_c_int64_t), "coupling_stiffness")
    write(output_unit, '(a)') "# K: (F, T, 2 pi R^2 p) = K (strain, twist per length, hoop strain)"
    do i = 1, 3
        do j = 1, 3
            call put("K_" // trim(names(i)) // "_" // trim(names(j)), k(i, j))
        end do
    end do

    call check(rodkit_thin_tube_stretch_twist(spec, s, 2_c_int64_t), "stretch_twist")
    write(output_unit, '(a)') "# condensed at p = 0: (F, T) = [[S, g], [g, C]] (strain, twist)"
    call put("stretch_modulus_S", s(1, 1))
    call put("twist_stretch_g", s(1, 2))
    call put("twist_modulus_C", s(2, 2))

    ! rod(6, 6): strains (u1, u2, u3, v1, v2, v3).
    call check(rodkit_thin_tube_rod_stiffness(spec, rod, 6_c_int64_t), "rod_stiffness")
    write(output_unit, '(a)') "# as a hemitropic rod: (m, n) = K6 (u, v - e3), strains (u1, u2, u3, v1, v2, v3)"
    call put("rod_bending", rod(1, 1))
    call put("rod_twist", rod(3, 3))
    call put("rod_shear", rod(4, 4))
    call put("rod_stretch", rod(6, 6))
    call put("rod_twist_stretch", rod(3, 6))
    call put("rod_bend_shear", rod(1, 4))

    call check(rodkit_thin_tube_free_response(spec, response), "free_response")
    call put("dstrain_dforce", response%dstrain_dforce)
    call put("dtwist_dforce", response%dtwist_dforce)
    call put("dhoop_dforce", response%dhoop_dforce)
    write(output_unit, '(a,i0)') "winding = ", response%winding
    select case (response%winding)
    case (RODKIT_WINDING_OVERWINDS)
        write(output_unit, '(a)') "# pulled with T = 0 the tube OVERWINDS (twists further in the sense of tau0)"
    case (RODKIT_WINDING_UNWINDS)
        write(output_unit, '(a)') "# pulled with T = 0 the tube unwinds"
    case default
        write(output_unit, '(a)') "# pulled with T = 0 the tube does not twist"
    end select

    ! A deliberate bad call: a negative transverse modulus must come back as
    ! RODKIT_STATUS_ERR_NOT_POSITIVE with a message naming spec.e2.
    bad = spec
    bad%e2 = -1.0_c_double
    st = rodkit_thin_tube_coupling_stiffness(bad, k, 3_c_int64_t)
    message = rodkit_last_error()
    write(output_unit, '(a,i0,a,a,a,a)') "# deliberate bad call (e2 -> -1): status ", st, " (", &
        rodkit_status_message(st), "): ", message
    if (st /= RODKIT_STATUS_ERR_NOT_POSITIVE .or. index(message, "spec.e2") == 0) then
        write(output_unit, '(a)') "error_caught = 0"
        write(error_unit, '(a,i0,a,a)') "the bad call was not reported as expected: status ", st, &
            ", message: ", message
        error stop 1
    end if
    write(output_unit, '(a)') "error_caught = 1"
    deallocate(path, message)

contains

    ! Stop with the status description and the last-error message on failure.
    subroutine check(status, what)
        integer(c_int32_t), intent(in) :: status
        character(len=*), intent(in) :: what
        if (status < 0) then
            write(error_unit, '(a,a,a,a,i0,a,a)') what, " failed: ", rodkit_status_message(status), " (", &
                status, "): ", rodkit_last_error()
            error stop 1
        end if
    end subroutine check

    ! One "name = value" line; 18 significant digits round-trip a double.
    ! A three-digit exponent field is used only where two digits do not fit
    ! (Fortran would drop the "E" otherwise).
    subroutine put(name, value)
        character(len=*), intent(in) :: name
        real(c_double), intent(in) :: value
        character(len=40) :: buffer
        ! (ieee_is_finite first: comparing a NaN would raise IEEE_INVALID.)
        if (.not. ieee_is_finite(value)) then
            write(buffer, '(es25.17)') value
        else if (abs(value) >= 1.0e99_c_double .or. &
                 (abs(value) > 0.0_c_double .and. abs(value) < 1.0e-98_c_double)) then
            write(buffer, '(es26.17e3)') value
        else
            write(buffer, '(es25.17)') value
        end if
        write(output_unit, '(a)') name // " = " // trim(adjustl(buffer))
    end subroutine put

end program tube_stiffness
