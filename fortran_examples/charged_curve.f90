! Electrostatic energy and writhe of a given curve from Fortran (physics.md
! 3.2-3.4): an open helix (radius 1, pitch 3, length 20, 81 nodes with unit
! tangents) carrying a uniform line charge 1 in a salt with kappa = 1 and
! excluded distance a = 0.3 -- the continuum energy with the near-field
! regularisation (near zones 0.8 and 0.4: independent of it), the discrete
! base-pair model at spacing 0.05, the writhe with the rays along the end
! tangents -- and the writhe of a closed toroidal helix (10 windings round
! the unit circle at amplitude 0.1). Prints "name = value" lines.
program charged_curve
    use, intrinsic :: iso_c_binding
    use rodkit
    implicit none
    integer, parameter :: n = 81, m = 401
    real(c_double), parameter :: pi = acos(-1.0_c_double)
    real(c_double), parameter :: radius = 1.0_c_double, pitch = 3.0_c_double, length = 20.0_c_double
    real(c_double) :: s(n), xyz(3, n), tan(3, n), sm(m), xm(3, m), tm(3, m)
    real(c_double) :: c, w, th, phi, rho, drho, dx(3), e_bp, wr, wr_helix
    type(rodkit_electrostatics_spec) :: spec
    type(rodkit_electrostatic_energy) :: energy, energy_narrow
    integer(c_int32_t) :: status
    integer :: k
    logical :: values
    character(len=16) :: flag

    ! --values (first argument): also every result as a "name = value" line
    ! (the channel rodkit's tests read); else a short report.
    values = .false.
    if (command_argument_count() >= 1) then
        call get_command_argument(1, flag)
        values = flag == '--values'
    end if

    c = pitch / (2.0_c_double * pi)
    w = sqrt(radius**2 + c**2)
    do k = 1, n
        s(k) = length * (k - 1) / (n - 1)
        th = s(k) / w
        xyz(:, k) = [radius * cos(th), radius * sin(th), c * th]
        tan(:, k) = [-radius * sin(th) / w, radius * cos(th) / w, c / w]
    end do

    status = rodkit_electrostatics_spec_default(spec)
    spec%line_charge = 1.0_c_double
    spec%kappa = 1.0_c_double
    spec%a = 0.3_c_double
    spec%near_width = 0.8_c_double
    spec%order = 12
    status = rodkit_curve_electrostatic_energy(s, xyz, 3_c_int64_t, tan, 3_c_int64_t, int(n, c_int64_t), 0, spec, energy)
    call check(status, 'rodkit_curve_electrostatic_energy')
    spec%near_width = 0.4_c_double
    status = rodkit_curve_electrostatic_energy(s, xyz, 3_c_int64_t, tan, 3_c_int64_t, int(n, c_int64_t), 0, spec, energy_narrow)
    call check(status, 'rodkit_curve_electrostatic_energy')
    status = rodkit_curve_base_pair_energy(s, xyz, 3_c_int64_t, tan, 3_c_int64_t, int(n, c_int64_t), 0, spec, 0.05_c_double, e_bp)
    call check(status, 'rodkit_curve_base_pair_energy')
    status = rodkit_curve_writhe(s, xyz, 3_c_int64_t, tan, 3_c_int64_t, int(n, c_int64_t), 0, 10_c_int64_t, wr)
    call check(status, 'rodkit_curve_writhe')
    if (values) print '(a)', '# rodkit ' // RODKIT_VERSION_STRING // ': open helix, radius 1, pitch 3, length 20, kappa 1, a 0.3'
    if (values) print '(a, es24.16)', 'energy = ', energy%total
    if (values) print '(a, es24.16)', 'energy_near = ', energy%near
    if (values) print '(a, es24.16)', 'energy_far = ', energy%far
    if (values) print '(a, es24.16)', 'energy_narrow_near_zone = ', energy_narrow%total
    if (values) print '(a, es24.16)', 'base_pair_energy = ', e_bp
    if (values) print '(a, es24.16)', 'helix_writhe = ', wr
    wr_helix = wr

    ! A closed toroidal helix, nodes equally spaced in phi; the arc lengths
    ! s(k) by Simpson's rule on |dr/dphi| (8 panels per interval); the last
    ! node repeats the first.
    sm(1) = 0.0_c_double
    do k = 1, m
        phi = 2.0_c_double * pi * (k - 1) / (m - 1)
        call toroidal(phi, xm(:, k), dx)
        tm(:, k) = dx / sqrt(sum(dx**2))
    end do
    do k = 2, m
        sm(k) = sm(k - 1) + arc(2.0_c_double * pi * (k - 2) / (m - 1), 2.0_c_double * pi * (k - 1) / (m - 1))
    end do
    status = rodkit_curve_writhe(sm, xm, 3_c_int64_t, tm, 3_c_int64_t, int(m, c_int64_t), 1, 10_c_int64_t, wr)
    call check(status, 'rodkit_curve_writhe (toroidal)')
    if (values) print '(a, es24.16)', 'toroidal_writhe = ', wr
    print '(a)', 'Electrostatics and writhe of given curves (screened line charge, kappa = 1, radius a = 0.3):'
    print '(a, f12.6, a, f12.6, a)', '  open helix (radius 1, pitch 3, length 20): energy', energy%total, &
        ' (base pairs every 0.05:', e_bp, ')'
    print '(a, f9.5, a, f10.6, a)', '  writhe: open helix', wr_helix, ', closed toroidal helix', wr, &
        ' (Fuller: -2.924540)'

contains
    subroutine toroidal(phi, r, dr)
        real(c_double), intent(in) :: phi
        real(c_double), intent(out) :: r(3), dr(3)
        rho = 1.0_c_double + 0.1_c_double * cos(10.0_c_double * phi)
        drho = -1.0_c_double * sin(10.0_c_double * phi)
        r = [rho * cos(phi), rho * sin(phi), 0.1_c_double * sin(10.0_c_double * phi)]
        dr = [drho * cos(phi) - rho * sin(phi), drho * sin(phi) + rho * cos(phi), cos(10.0_c_double * phi)]
    end subroutine toroidal

    function arc(p0, p1) result(length_)
        real(c_double), intent(in) :: p0, p1
        real(c_double) :: length_, r(3), dr(3), h, p
        integer :: i
        h = (p1 - p0) / 8
        length_ = 0.0_c_double
        do i = 0, 8
            p = p0 + i * h
            call toroidal(p, r, dr)
            if (i == 0 .or. i == 8) then
                length_ = length_ + sqrt(sum(dr**2))
            else if (mod(i, 2) == 1) then
                length_ = length_ + 4 * sqrt(sum(dr**2))
            else
                length_ = length_ + 2 * sqrt(sum(dr**2))
            end if
        end do
        length_ = length_ * h / 3
    end function arc

    subroutine check(status, what)
        integer(c_int32_t), intent(in) :: status
        character(*), intent(in) :: what
        if (status < 0) then
            print '(a)', what // ' failed: ' // rodkit_last_error()
            error stop 1
        end if
    end subroutine check
end program charged_curve
