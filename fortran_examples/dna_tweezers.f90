! DNA in magnetic tweezers at finite temperature from Fortran (physics.md
! 3.7): the thermal two-phase model's curve for the default scene (1 kbp,
! 1 pN, 0.1 M, kT 4.11 pN nm), 200 points from 0 to twice the buckling
! turns, and its summary (the numbers c_examples/dna_tweezers.c prints with
! --values); then a spec with a negative force, refused with its status and
! message. Exercises the tweezers handle through the module's bind(c)
! types. Prints "name = value" lines.
program dna_tweezers
    use, intrinsic :: iso_c_binding
    use rodkit
    implicit none
    integer(c_int64_t), parameter :: n = 200
    type(rodkit_tweezers_spec) :: spec
    type(rodkit_tweezers_info) :: summary
    type(rodkit_tweezers_point) :: points(n)
    real(c_double) :: turns(n)
    type(c_ptr) :: tweezers, refused
    integer(c_int32_t) :: status

    status = rodkit_tweezers_spec_default(spec)
    call check(status, 'rodkit_tweezers_spec_default')
    status = rodkit_tweezers_new(spec, tweezers)
    call check(status, 'rodkit_tweezers_new')
    status = rodkit_tweezers_default_turns(tweezers, n, turns)
    call check(status, 'rodkit_tweezers_default_turns')
    status = rodkit_tweezers_curve(tweezers, turns, n, points)
    call check(status, 'rodkit_tweezers_curve')
    status = rodkit_tweezers_summary(tweezers, points, n, summary)
    call check(status, 'rodkit_tweezers_summary')
    call rodkit_tweezers_free(tweezers)

    print '(a)', '# rodkit ' // RODKIT_VERSION_STRING // ': DNA in tweezers, 1 kbp, 1 pN, 0.1 M, kT 4.11 pN nm, 200 points'
    print '(a, es24.16)', 'force = ', spec%force
    print '(a, es24.16)', 'salt = ', spec%salt
    print '(a, es24.16)', 'base_pairs = ', spec%base_pairs
    print '(a, es24.16)', 'kT = ', spec%kt
    print '(a, i0)', 'points = ', n
    print '(a, i0)', 'model = ', summary%model
    print '(a, i0)', 'end_loop = ', summary%end_loop
    print '(a, es24.16)', 'buckling_turns = ', summary%buckling_turns
    print '(a, es24.16)', 'buckling_torque = ', summary%buckling_torque
    print '(a, es24.16)', 'plateau_torque = ', summary%plateau_torque
    print '(a, es24.16)', 'plateau_torque_min = ', summary%plateau_torque_min
    print '(a, es24.16)', 'plateau_torque_max = ', summary%plateau_torque_max
    print '(a, es24.16)', 'overshoot = ', summary%overshoot
    print '(a, es24.16)', 'coexistence_torque = ', summary%coexistence_torque
    print '(a, es24.16)', 'slope = ', summary%slope
    print '(a, es24.16)', 'extension_jump = ', summary%extension_jump
    print '(a, es24.16)', 'extension_zero_turns = ', summary%extension_zero_turns
    print '(a, es24.16)', 'superhelix_radius = ', summary%superhelix_radius
    print '(a, es24.16)', 'superhelix_angle = ', summary%superhelix_angle
    print '(a, es24.16)', 'end_loop_energy = ', summary%end_loop_energy
    print '(a, es24.16)', 'end_loop_correction = ', summary%end_loop_correction
    print '(a, es24.16)', 'plateau_turns_from = ', summary%plateau_turns_from
    print '(a, es24.16)', 'plateau_turns_to = ', summary%plateau_turns_to
    print '(a, i0)', 'plateau_points = ', summary%plateau_points
    print '(a, es24.16)', 'last_turns = ', points(n)%turns
    print '(a, es24.16)', 'last_extension = ', points(n)%extension
    print '(a, es24.16)', 'last_torque = ', points(n)%torque
    print '(a, es24.16)', 'last_plectonemes = ', points(n)%plectonemes

    ! A negative force: refused, no handle, the field named in the message.
    spec%force = -1.0_c_double
    status = rodkit_tweezers_new(spec, refused)
    print '(a, i0)', 'negative_force_status = ', status
    print '(a, l1)', '# negative force: no handle: ', .not. c_associated(refused)
    print '(a)', '# negative force: ' // rodkit_last_error()

contains
    subroutine check(status, what)
        integer(c_int32_t), intent(in) :: status
        character(*), intent(in) :: what
        if (status < 0) then
            print '(a)', what // ' failed: ' // rodkit_last_error()
            error stop 1
        end if
    end subroutine check
end program dna_tweezers
