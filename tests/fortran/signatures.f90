! Calls the generated module's interfaces of every argument kind the
! generator maps (tests/fortran_module.rs builds and runs it, and compares
! the printed `name = value` lines with closed forms and with the same C
! functions called from Rust):
!  - scalars by value (real, integer(c_int32_t), integer(c_int64_t), seven
!    reals in a row: rodkit_dna_fit_thin_wall), scalar outputs, the result
!    named `version`;
!  - arrays in, inout with a leading dimension (padding rows untouched), and
!    of derived types; derived types in and out (a struct in a struct);
!  - handles out and by value, C strings in and out (truncation), a C string
!    returned as type(c_ptr);
!  - a callback through c_funloc with user data through c_loc, declared with
!    the generated abstract interface.
! Any failed expectation stops with a non-zero code and says which.
module signatures_callback
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_ptr, c_f_pointer
    use rodkit, only: rodkit_branch_progress, rodkit_branch_callback
    implicit none
    ! The callback must match the generated abstract interface.
    procedure(rodkit_branch_callback), pointer :: checked => cancel_at_first
contains
    function cancel_at_first(progress, user_data) result(status) bind(c)
        type(rodkit_branch_progress), intent(in) :: progress
        type(c_ptr), value :: user_data
        integer(c_int32_t) :: status
        integer(c_int64_t), pointer :: calls
        call c_f_pointer(user_data, calls)
        calls = calls + 1
        status = 1
        if (progress%lambda < 0) status = 1
    end function cancel_at_first
end module signatures_callback

program signatures
    use, intrinsic :: iso_c_binding
    use rodkit
    use signatures_callback
    implicit none
    real(c_double), parameter :: pi = acos(-1.0_c_double)
    type(rodkit_thin_tube_spec) :: tube
    type(rodkit_dna_fit) :: fit
    type(rodkit_rod_spec) :: spec
    type(rodkit_continuation_options) :: opts
    type(rodkit_branch_info) :: info
    type(rodkit_branch_record), allocatable :: rec(:)
    type(c_ptr) :: rod, branch
    integer(c_int32_t) :: st, major, minor, patch
    integer(c_int64_t) :: n, count, length
    integer(c_int64_t), target :: calls
    real(c_double) :: s(3, 2), k(2, 3), nodes(8), tip(3), quaternion(4), force(3), moment(3), writhe, alpha
    real(c_double), allocatable :: x(:), r(:)
    real(c_double) :: t(41), s_knot(41), xyz(3, 41), tangents(3, 41)
    character(len=6, kind=c_char) :: small
    character(len=256) :: csv
    character(len=:), allocatable :: message
    integer :: i
    logical :: exists

    ! Versions: the run-time library against the module's parameters.
    st = rodkit_version(major, minor, patch)
    call expect(st == RODKIT_STATUS_OK .and. major == RODKIT_VERSION_MAJOR .and. minor == RODKIT_VERSION_MINOR &
        .and. patch == RODKIT_VERSION_PATCH, 'rodkit_version against RODKIT_VERSION_*')
    call expect(rodkit_library_abi_version() == RODKIT_ABI_VERSION, 'rodkit_library_abi_version')
    print '(a)', 'status_err_io = ' // rodkit_status_message(RODKIT_STATUS_ERR_IO)

    ! An isotropic thin tube (E = 1000, nu = 0.3, R = 2, t = 0.05, no twist):
    ! the condensed stretch-twist law into s(3, 2) with lds = 3, row 3 a
    ! sentinel that must stay.
    st = rodkit_thin_tube_spec_default(tube)
    tube%mid_radius = 2.0_c_double
    tube%thickness = 0.05_c_double
    tube%intrinsic_twist = 0.0_c_double
    tube%e1 = 1000.0_c_double
    tube%e2 = 1000.0_c_double
    tube%nu12 = 0.3_c_double
    tube%g12 = 1000.0_c_double / 2.6_c_double
    s = 7.0_c_double
    st = rodkit_thin_tube_stretch_twist(tube, s, 3_c_int64_t)
    call expect(st == RODKIT_STATUS_OK, 'rodkit_thin_tube_stretch_twist: ' // rodkit_last_error())
    call expect(all(abs(s(3, :) - 7) <= 0), 'padding row of s untouched')
    print '(a, es24.16)', 'iso_stretch = ', s(1, 1)
    print '(a, es24.16)', 'iso_coupling = ', s(1, 2)
    print '(a, es24.16)', 'iso_twist = ', s(2, 2)

    ! A refused leading dimension: the status, the message naming `ldk`, a
    ! truncated copy of it (6 bytes: 5 characters and the NUL).
    st = rodkit_thin_tube_coupling_stiffness(tube, k, 2_c_int64_t)
    call expect(st == RODKIT_STATUS_ERR_INVALID_DIMENSION, 'ldk = 2 refused')
    call expect(index(rodkit_last_error(), 'ldk') > 0, 'the message names ldk: ' // rodkit_last_error())
    message = rodkit_last_error()
    st = rodkit_last_error_copy(small, 6_c_int64_t, length)
    call expect(st == RODKIT_STATUS_INFO_TRUNCATED .and. length == len(message), &
        'rodkit_last_error_copy truncates and reports the full length')
    call expect(small(6:6) == c_null_char .and. small(1:5) == message(1:5), 'truncated copy')

    ! Seven reals by value, in order: fit the thin wall back from the
    ! condensed law of an orthotropic tube with a helix angle of 0.6 rad.
    tube%mid_radius = 1.0_c_double
    tube%thickness = 0.4_c_double
    tube%intrinsic_twist = tan(0.6_c_double)
    tube%e1 = 300.0_c_double
    tube%e2 = 900.0_c_double
    tube%nu12 = 0.3_c_double
    tube%g12 = 100.0_c_double
    st = rodkit_thin_tube_helix_angle(tube, alpha)
    call expect(st == RODKIT_STATUS_OK, 'rodkit_thin_tube_helix_angle')
    st = rodkit_thin_tube_stretch_twist(tube, s, 3_c_int64_t)
    st = rodkit_dna_fit_thin_wall(s(1, 1), s(2, 2), s(1, 2), 1.0_c_double, alpha, 0.4_c_double, 0.3_c_double, fit)
    call expect(st >= 0, 'rodkit_dna_fit_thin_wall: ' // rodkit_last_error())
    print '(a, es24.16)', 'helix_angle = ', alpha
    print '(a, es24.16)', 'fit_e1 = ', fit%spec%e1
    print '(a, es24.16)', 'fit_e2 = ', fit%spec%e2
    print '(a, es24.16)', 'fit_g12 = ', fit%spec%g12
    print '(a, es24.16)', 'fit_coupling = ', fit%coupling
    print '(a, es24.16)', 'law_coupling = ', s(1, 2)

    ! A cantilever of 4 Gauss(2) elements: handle out, counts out, arrays.
    st = rodkit_rod_spec_default(spec)
    spec%length = 2.0_c_double
    spec%bending1 = 3.0_c_double
    spec%bending2 = 3.0_c_double
    spec%twist = 2.0_c_double
    spec%shear1 = 1.0e3_c_double
    spec%shear2 = 1.0e3_c_double
    spec%stretch = 4.0e3_c_double
    spec%tip_force_frame = RODKIT_LOAD_FRAME_DEAD
    spec%tip_force_x = 1.0_c_double
    spec%scheme = RODKIT_ROD_SCHEME_GAUSS
    spec%stages = 2
    spec%elements = 4
    st = rodkit_rod_new(spec, rod)
    call expect(st == RODKIT_STATUS_OK .and. c_associated(rod), 'rodkit_rod_new: ' // rodkit_last_error())
    st = rodkit_rod_unknowns(rod, n)
    print '(a, i0)', 'unknowns = ', n
    nodes = -1.0_c_double
    st = rodkit_rod_node_positions(rod, nodes, 3_c_int64_t, count)
    call expect(st == RODKIT_STATUS_INFO_TRUNCATED .and. count == 5 .and. abs(nodes(4) + 1) <= 0, &
        'rodkit_rod_node_positions truncates to its capacity')
    st = rodkit_rod_node_positions(rod, nodes, 8_c_int64_t, count)
    print '(a, *(es24.16, :, ", "))', 'node_positions = ', nodes(1:count)
    allocate(x(n), r(n))
    st = rodkit_rod_straight_state(rod, x, n)
    r = 1.0_c_double
    st = rodkit_rod_residual(rod, x, n, 0.0_c_double, r)
    call expect(st == RODKIT_STATUS_OK, 'rodkit_rod_residual: ' // rodkit_last_error())
    print '(a, es24.16)', 'straight_residual = ', maxval(abs(r))

    ! The callback cancels at its first call: the status says so.
    st = rodkit_continuation_options_default(opts)
    opts%target_lambda = 1.0e-3_c_double
    calls = 0
    st = rodkit_rod_continue(rod, x, n, 0.0_c_double, opts, c_funloc(cancel_at_first), c_loc(calls), branch)
    call expect(st == RODKIT_STATUS_INFO_CANCELLED .and. calls == 1, 'cancelled by the callback at its first call')
    call rodkit_branch_free(branch)
    ! To a small dead tip load P = 1e-3: the tip deflection against linear
    ! beam theory, P L^3 / (3 B) + P L / GA.
    st = rodkit_rod_continue(rod, x, n, 0.0_c_double, opts, c_null_funptr, c_null_ptr, branch)
    call expect(st == RODKIT_STATUS_OK, 'rodkit_rod_continue: ' // rodkit_last_error())
    st = rodkit_branch_summary(branch, info)
    allocate(rec(info%records))
    st = rodkit_branch_records(branch, rec, info%records, count)
    call expect(st == RODKIT_STATUS_OK .and. count == info%records, 'rodkit_branch_records')
    print '(a, es24.16)', 'final_lambda = ', rec(count)%lambda
    print '(a, es24.16)', 'tip_x = ', rec(count)%tip_x
    st = rodkit_branch_state(branch, count - 1, x, n)
    call expect(st == RODKIT_STATUS_OK, 'rodkit_branch_state: ' // rodkit_last_error())
    st = rodkit_rod_node_state(rod, x, n, 4_c_int64_t, tip, quaternion, force, moment)
    call expect(st == RODKIT_STATUS_OK .and. abs(tip(1) - rec(count)%tip_x) <= 0, 'rodkit_rod_node_state tip = record tip')
    ! The tip carries the load: n = (P, 0, 0), m = 0 (dead load, spatial frame).
    print '(a, es24.16)', 'tip_force_x = ', force(1)
    print '(a, es24.16)', 'tip_moment = ', norm2(moment)
    print '(a, es24.16)', 'tip_quaternion_norm = ', norm2(quaternion)

    ! A C string in: the branch as CSV.
    call get_command_argument(1, csv)
    st = rodkit_branch_write_csv(branch, rod, trim(csv) // c_null_char)
    inquire(file=trim(csv), exist=exists)
    call expect(st == RODKIT_STATUS_OK .and. exists, 'rodkit_branch_write_csv: ' // rodkit_last_error())
    call rodkit_branch_free(branch)
    call rodkit_rod_free(rod)

    ! Arrays with leading dimensions and an int32 flag by value: the writhe
    ! of a closed (2, 3) torus knot, 40 pieces (node 41 repeats node 1), s
    ! its arc length (Simpson, 64 panels a piece, of the speed
    ! sqrt(9 + 4 (2 + cos 3t)^2)); then of its mirror image, which must be
    ! the negative.
    do i = 1, 41
        t(i) = 2 * pi * (i - 1) / 40
    end do
    s_knot(1) = 0
    do i = 2, 41
        s_knot(i) = s_knot(i - 1) + piece_length(t(i - 1), t(i))
    end do
    do i = 1, 41
        xyz(:, i) = knot(t(i))
        tangents(:, i) = [-3 * sin(3 * t(i)) * cos(2 * t(i)) - 2 * (2 + cos(3 * t(i))) * sin(2 * t(i)), &
            -3 * sin(3 * t(i)) * sin(2 * t(i)) + 2 * (2 + cos(3 * t(i))) * cos(2 * t(i)), 3 * cos(3 * t(i))]
    end do
    xyz(:, 41) = xyz(:, 1)
    tangents(:, 41) = tangents(:, 1)
    st = rodkit_curve_writhe(s_knot, xyz, 3_c_int64_t, tangents, 3_c_int64_t, 41_c_int64_t, 1_c_int32_t, &
        8_c_int64_t, writhe)
    call expect(st >= 0, 'rodkit_curve_writhe: ' // rodkit_last_error())
    print '(a, es24.16)', 'torus_knot_writhe = ', writhe
    xyz(3, :) = -xyz(3, :)
    tangents(3, :) = -tangents(3, :)
    st = rodkit_curve_writhe(s_knot, xyz, 3_c_int64_t, tangents, 3_c_int64_t, 41_c_int64_t, 1_c_int32_t, &
        8_c_int64_t, writhe)
    call expect(st >= 0, 'rodkit_curve_writhe (mirror): ' // rodkit_last_error())
    print '(a, es24.16)', 'mirror_knot_writhe = ', writhe
    print '(a)', 'signatures: all expectations met'

contains

    subroutine expect(ok, what)
        logical, intent(in) :: ok
        character(len=*), intent(in) :: what
        if (.not. ok) then
            print '(a)', 'FAILED: ' // what
            error stop 1
        end if
    end subroutine expect

    pure function knot(u) result(p)
        real(c_double), intent(in) :: u
        real(c_double) :: p(3)
        p = [(2 + cos(3 * u)) * cos(2 * u), (2 + cos(3 * u)) * sin(2 * u), sin(3 * u)]
    end function knot

    pure function piece_length(a, b) result(total)
        real(c_double), intent(in) :: a, b
        real(c_double) :: total, h
        integer :: j
        h = (b - a) / 64
        total = speed(a) + speed(b)
        do j = 1, 63
            total = total + merge(4, 2, mod(j, 2) == 1) * speed(a + j * h)
        end do
        total = total * h / 3
    end function piece_length

    pure function speed(u) result(v)
        real(c_double), intent(in) :: u
        real(c_double) :: v
        v = sqrt(9 + 4 * (2 + cos(3 * u))**2)
    end function speed

end program signatures
