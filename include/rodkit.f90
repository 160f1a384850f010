!
! rodkit: mechanics of elastic tubes and rods, Fortran 2008 interface.
!
! Hand-written ISO_C_BINDING mirror of include/rodkit.h (which cbindgen
! generates from the Rust sources). tests/fortran_interface.rs parses both
! files and fails when they drift: every function, argument (name, order,
! type, VALUE), struct field, enumerator and RODKIT_ macro of the header must
! appear here, and nothing else named rodkit_* with BIND(C).
!
! Build:  gfortran -std=f2008 -c include/rodkit.f90 -J <moddir>
!         then `use rodkit` and link with -lrodkit (or librodkit.a).
!
! Conventions (all functions, as in the header):
!  - Fallible functions return integer(c_int32_t): 0 success, > 0 success
!    with information, < 0 failure (RODKIT_STATUS_*). `if (st < 0)` catches
!    every failure.
!  - After a failure, rodkit_last_error() (module procedure below) returns a
!    message naming the offending argument and value (thread-local).
!  - Matrices are column-major with an explicit leading dimension, i.e. plain
!    Fortran arrays: pass k(ldk, 3) as `k` and `ldk`. Arrays are owned by the
!    caller and borrowed for the duration of the call only; rodkit keeps no
!    pointer to them.
!  - Every function is reentrant and thread-safe on distinct arguments;
!    rodkit starts no threads unless asked per call or per handle.
!  - Character arguments are C strings: NUL-terminated arrays of
!    character(kind=c_char). Returned `type(c_ptr)` strings are owned by
!    rodkit (never deallocate them); convert them with the module procedures
!    rodkit_status_message and rodkit_last_error.
!
module rodkit
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_double, c_char, c_ptr, c_funptr, &
        c_null_char, c_associated, c_f_pointer
    implicit none
    private :: c_string_to_fortran

    ! -------------------------------------------------------------------------
    ! Library version (from Cargo.toml) and ABI version (from src/version.rs)
    ! of the header this module mirrors. Compare them with rodkit_version()
    ! and rodkit_library_abi_version() at
    ! run time to detect a module/library mismatch.
    ! -------------------------------------------------------------------------
    integer(c_int32_t), parameter :: RODKIT_VERSION_MAJOR = 0
    integer(c_int32_t), parameter :: RODKIT_VERSION_MINOR = 1
    integer(c_int32_t), parameter :: RODKIT_VERSION_PATCH = 0
    character(len=*), parameter :: RODKIT_VERSION_STRING = "0.1.0"
    integer(c_int32_t), parameter :: RODKIT_ABI_VERSION = 2

    ! -------------------------------------------------------------------------
    ! enum RodkitStatus: status returned by every fallible rodkit function.
    ! -------------------------------------------------------------------------
    ! success
    integer(c_int32_t), parameter :: RODKIT_STATUS_OK = 0
    ! success, but the output was truncated to fit the caller's buffer
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_TRUNCATED = 1
    ! stopped early at the request of the progress callback (results so far are valid)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_CANCELLED = 2
    ! the continuation stopped at its step limit before reaching its target
    ! (the branch so far is valid)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_STEP_LIMIT = 3
    ! the continuation left the allowed parameter range before reaching its
    ! target (the branch so far is valid)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_LAMBDA_RANGE = 4
    ! the continuation step fell below its minimum: the branch could not be
    ! followed further (the branch so far is valid)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_STEP_TOO_SMALL = 5
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_STRAND_CROSSING = 6
    ! the computation failed partway and kept its results up to the last
    ! good point (the handle's failure report gives the error and its message)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_FAILED_PARTWAY = 7
    ! the branch is complete, but a monitored function changed sign where no
    ! bifurcation accounting for it was located (the branch's unresolved
    ! brackets say where)
    integer(c_int32_t), parameter :: RODKIT_STATUS_INFO_UNRESOLVED_BIFURCATION = 8
    ! internal error (a bug in rodkit: a panic was caught at the C boundary)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_INTERNAL = -1
    ! a required pointer argument is NULL
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NULL_POINTER = -2
    ! a numeric argument is NaN or infinite
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NOT_FINITE = -3
    ! a numeric argument that must be positive is zero or negative
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NOT_POSITIVE = -4
    ! a numeric argument is outside its allowed range
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_OUT_OF_RANGE = -5
    ! the material constants do not give a positive-definite stiffness
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NOT_POSITIVE_DEFINITE = -6
    ! the geometry is impossible (inverted or degenerate sizes)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_INVALID_GEOMETRY = -7
    ! an array's length or leading dimension is inconsistent with the problem
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_INVALID_DIMENSION = -8
    ! an iterative solver did not converge to the requested tolerance
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NOT_CONVERGED = -9
    ! a computed result is not finite (overflow or an ill-posed problem)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_NON_FINITE_RESULT = -10
    ! the material lost stability at the requested state (e.g. Saint
    ! Venant-Kirchhoff in strong compression)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_MATERIAL_INSTABILITY = -11
    ! the call would exceed its work bound (the message gives the estimated
    ! cost and the bound); nothing was computed
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_WORK_LIMIT = -12
    ! the requested tolerance is below what the model or floating-point
    ! round-off can reach (the message gives the best reachable)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_TOLERANCE_UNREACHABLE = -13
    ! a file could not be written (the message names the path and the system's reason)
    integer(c_int32_t), parameter :: RODKIT_STATUS_ERR_IO = -14

    ! -------------------------------------------------------------------------
    ! enum RodkitWinding: how a free tube (T = 0, p = 0) twists when pulled,
    ! relative to the sense of its intrinsic twist tau0.
    ! -------------------------------------------------------------------------
    ! Twists against tau0 (the usual response of a helical structure).
    integer(c_int32_t), parameter :: RODKIT_WINDING_UNWINDS = -1
    ! No extension-twist coupling (tau0 = 0, or |coupling| at round-off level).
    integer(c_int32_t), parameter :: RODKIT_WINDING_NEITHER = 0
    ! Twists further in the sense of tau0 (DNA's counter-intuitive response).
    integer(c_int32_t), parameter :: RODKIT_WINDING_OVERWINDS = 1

    ! enum RodkitWallLawKind (RodkitWallMaterialSpec%law)
    integer(c_int32_t), parameter :: RODKIT_WALL_LAW_KIND_UNSET = 0
    integer(c_int32_t), parameter :: RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF = 1
    integer(c_int32_t), parameter :: RODKIT_WALL_LAW_KIND_NEO_HOOKEAN = 2
    integer(c_int32_t), parameter :: RODKIT_WALL_LAW_KIND_FIBRE_REINFORCED = 3
    ! enum RodkitTubeModel (RodkitTubeSpec%model, RodkitTubeState%model)
    integer(c_int32_t), parameter :: RODKIT_TUBE_MODEL_AUTO = 0
    integer(c_int32_t), parameter :: RODKIT_TUBE_MODEL_THICK = 1
    integer(c_int32_t), parameter :: RODKIT_TUBE_MODEL_MEMBRANE = 2
    ! enum RodkitAxialControl, enum RodkitTorsionControl (RodkitTubeLoading)
    integer(c_int32_t), parameter :: RODKIT_AXIAL_CONTROL_STRETCH = 0
    integer(c_int32_t), parameter :: RODKIT_AXIAL_CONTROL_FORCE = 1
    integer(c_int32_t), parameter :: RODKIT_TORSION_CONTROL_TWIST = 0
    integer(c_int32_t), parameter :: RODKIT_TORSION_CONTROL_TORQUE = 1

    ! enum RodkitRodSupports (see rodkit.h).
    integer(c_int32_t), parameter :: RODKIT_ROD_SUPPORTS_CANTILEVER = 1
    integer(c_int32_t), parameter :: RODKIT_ROD_SUPPORTS_CLAMPED = 2
    integer(c_int32_t), parameter :: RODKIT_ROD_SUPPORTS_PINNED = 3
    integer(c_int32_t), parameter :: RODKIT_ROD_SUPPORTS_TWISTED = 4
    integer(c_int32_t), parameter :: RODKIT_ROD_SUPPORTS_TORQUED = 5

    ! enum RodkitLoadFrame (see rodkit.h).
    integer(c_int32_t), parameter :: RODKIT_LOAD_FRAME_NONE = 0
    integer(c_int32_t), parameter :: RODKIT_LOAD_FRAME_DEAD = 1
    integer(c_int32_t), parameter :: RODKIT_LOAD_FRAME_FOLLOWER = 2

    ! enum RodkitRodScheme (see rodkit.h).
    integer(c_int32_t), parameter :: RODKIT_ROD_SCHEME_MIDPOINT = 1
    integer(c_int32_t), parameter :: RODKIT_ROD_SCHEME_GAUSS = 2

    ! enum RodkitContinuationMethod (see rodkit.h).
    integer(c_int32_t), parameter :: RODKIT_CONTINUATION_METHOD_ANM = 1
    integer(c_int32_t), parameter :: RODKIT_CONTINUATION_METHOD_NEWTON = 2

    ! enum RodkitBranchStop (see rodkit.h).
    integer(c_int32_t), parameter :: RODKIT_BRANCH_STOP_TARGET = 0
    integer(c_int32_t), parameter :: RODKIT_BRANCH_STOP_LAMBDA_RANGE = 1
    integer(c_int32_t), parameter :: RODKIT_BRANCH_STOP_MAX_STEPS = 2
    integer(c_int32_t), parameter :: RODKIT_BRANCH_STOP_CANCELLED = 3
    integer(c_int32_t), parameter :: RODKIT_BRANCH_STOP_STEP_TOO_SMALL = 4
    integer(c_int32_t), parameter :: RODKIT_EQUILIBRIUM_SOLVER_DIRECT = 1
    integer(c_int32_t), parameter :: RODKIT_EQUILIBRIUM_SOLVER_NEWTON_KRYLOV = 2
    integer(c_int32_t), parameter :: RODKIT_END_CONTROL_ROTATION = 1
    integer(c_int32_t), parameter :: RODKIT_END_CONTROL_TORQUE = 2

    ! RodkitSupercoilStop (rodkit_supercoil_stop).
    integer(c_int32_t), parameter :: RODKIT_SUPERCOIL_STOP_FINISHED = 0
    integer(c_int32_t), parameter :: RODKIT_SUPERCOIL_STOP_CANCELLED = 1
    integer(c_int32_t), parameter :: RODKIT_SUPERCOIL_STOP_FAILED = 2

    ! RodkitSummaryFinding (rodkit_supercoil_curve_summary).
    integer(c_int32_t), parameter :: RODKIT_SUMMARY_FINDING_FOUND = 1
    integer(c_int32_t), parameter :: RODKIT_SUMMARY_FINDING_UNVERIFIED = 2
    integer(c_int32_t), parameter :: RODKIT_SUMMARY_FINDING_UNDETERMINED = 3
    integer(c_int32_t), parameter :: RODKIT_SUMMARY_FINDING_NOT_REACHED = 4

    ! RodkitStabilityKind (rodkit_supercoil_curve_points).
    integer(c_int32_t), parameter :: RODKIT_STABILITY_KIND_LOWEST = 1
    integer(c_int32_t), parameter :: RODKIT_STABILITY_KIND_METASTABLE = 2
    integer(c_int32_t), parameter :: RODKIT_STABILITY_KIND_UNSTABLE = 3
    integer(c_int32_t), parameter :: RODKIT_STABILITY_KIND_UNDETERMINED = 4


    ! -------------------------------------------------------------------------
    ! RodkitThinTubeSpec: a thin helically reinforced tube in its stress-free
    ! state (physics.md 1.4): geometry, intrinsic twist and in-surface
    ! orthotropic constants. Units are the caller's, used consistently (e.g.
    ! nm and pN/nm^2).
    !
    ! Initialise with rodkit_thin_tube_spec_default, which sets every field to
    ! NaN ("unset": a forgotten field is rejected by name), then set them all.
    ! -------------------------------------------------------------------------
    type, bind(c) :: rodkit_thin_tube_spec
        ! Mid-surface radius R > 0.
        real(c_double) :: mid_radius
        ! Wall thickness t, 0 < t < 2R.
        real(c_double) :: thickness
        ! Intrinsic twist tau0 (1/length; any sign = handedness): the
        ! reinforcement follows a helix at angle atan(tau0*R) from the axis.
        real(c_double) :: intrinsic_twist
        ! Young's modulus along the reinforcement, E1 > 0.
        real(c_double) :: e1
        ! Young's modulus across the reinforcement (in the surface), E2 > 0.
        real(c_double) :: e2
        ! Major Poisson ratio nu12, with nu12**2 < E1/E2 (positive definiteness).
        real(c_double) :: nu12
        ! In-surface shear modulus G12 > 0.
        real(c_double) :: g12
    end type rodkit_thin_tube_spec

    ! -------------------------------------------------------------------------
    ! RodkitFreeTubeResponse: response of a free thin tube (zero torque, zero
    ! pressure) to an axial force F, per unit force.
    ! -------------------------------------------------------------------------
    type, bind(c) :: rodkit_free_tube_response
        ! d(strain)/dF: axial strain per force.
        real(c_double) :: dstrain_dforce
        ! d(psi)/dF: twist per length per force.
        real(c_double) :: dtwist_dforce
        ! d(hoop strain)/dF: hoop strain per force (> 0: inflates when stretched).
        real(c_double) :: dhoop_dforce
        ! RODKIT_WINDING_*: +1 overwinds (twists further in the sense of tau0),
        ! -1 unwinds, 0 neither (tau0 = 0 or no coupling).
        integer(c_int32_t) :: winding
    end type rodkit_free_tube_response

    ! -------------------------------------------------------------------------
    ! RodkitWallMaterialSpec: the wall material (see rodkit.h). Initialise with
    ! rodkit_wall_material_spec_default, then set the chosen law's fields.
    ! -------------------------------------------------------------------------
    type, bind(c) :: rodkit_wall_material_spec
        integer(c_int32_t) :: law
        integer(c_int32_t) :: incompressible
        real(c_double) :: intrinsic_twist
        real(c_double) :: e1
        real(c_double) :: e2
        real(c_double) :: e3
        real(c_double) :: nu12
        real(c_double) :: nu13
        real(c_double) :: nu23
        real(c_double) :: g12
        real(c_double) :: g13
        real(c_double) :: g23
        real(c_double) :: shear_modulus
        real(c_double) :: lame_lambda
        integer(c_int64_t) :: fibre_families
        real(c_double) :: fibre1_k1
        real(c_double) :: fibre1_k2
        real(c_double) :: fibre1_angle
        real(c_double) :: fibre1_hand
        real(c_double) :: fibre2_k1
        real(c_double) :: fibre2_k2
        real(c_double) :: fibre2_angle
        real(c_double) :: fibre2_hand
    end type rodkit_wall_material_spec

    ! RodkitTubeSpec: geometry, material, model choice and tolerance.
    type, bind(c) :: rodkit_tube_spec
        real(c_double) :: inner_radius
        real(c_double) :: outer_radius
        type(rodkit_wall_material_spec) :: material
        integer(c_int32_t) :: model
        real(c_double) :: rel_tol
        integer(c_int64_t) :: intervals
    end type rodkit_tube_spec

    ! RodkitTubeLoading: (stretch | force), (twist | torque), pressures, ends.
    type, bind(c) :: rodkit_tube_loading
        integer(c_int32_t) :: axial_control
        real(c_double) :: axial
        integer(c_int32_t) :: torsion_control
        real(c_double) :: torsion
        real(c_double) :: inner_pressure
        real(c_double) :: outer_pressure
        integer(c_int32_t) :: closed_ends
    end type rodkit_tube_loading

    ! RodkitTubeState: an equilibrium state.
    type, bind(c) :: rodkit_tube_state
        real(c_double) :: stretch
        real(c_double) :: twist
        real(c_double) :: wall_force
        real(c_double) :: applied_force
        real(c_double) :: torque
        real(c_double) :: inner_pressure
        real(c_double) :: outer_pressure
        real(c_double) :: deformed_inner_radius
        real(c_double) :: deformed_outer_radius
        real(c_double) :: error_estimate
        integer(c_int64_t) :: intervals
        integer(c_int64_t) :: newton_iterations
        integer(c_int32_t) :: model
    end type rodkit_tube_state

    ! RodkitDnaFit: a thin-wall fit to a stretch-twist law (see rodkit.h).
    type, bind(c) :: rodkit_dna_fit
        type(rodkit_thin_tube_spec) :: spec
        real(c_double) :: stretch
        real(c_double) :: coupling
        real(c_double) :: twist
        real(c_double) :: twist_rate
        real(c_double) :: turns_per_pn_per_10kbp
        integer(c_int32_t) :: overwinds
        integer(c_int32_t) :: thick_status
        real(c_double) :: thick_stretch
        real(c_double) :: thick_coupling
        real(c_double) :: thick_twist
        real(c_double) :: thick_turns_per_pn_per_10kbp
    end type rodkit_dna_fit

    ! RodkitProgress: what a progress callback is told.
    type, bind(c) :: rodkit_progress
        integer(c_int64_t) :: done
        integer(c_int64_t) :: total
    end type rodkit_progress

    ! RodkitRodSpec (see rodkit.h).
    type, bind(c) :: rodkit_rod_spec
        real(c_double) :: length
        integer(c_int32_t) :: kirchhoff
        real(c_double) :: bending1
        real(c_double) :: bending2
        real(c_double) :: twist
        real(c_double) :: shear1
        real(c_double) :: shear2
        real(c_double) :: stretch
        real(c_double) :: twist_stretch
        real(c_double) :: bend_shear
        real(c_double) :: intrinsic_u1
        real(c_double) :: intrinsic_u2
        real(c_double) :: intrinsic_u3
        real(c_double) :: intrinsic_v1
        real(c_double) :: intrinsic_v2
        real(c_double) :: intrinsic_v3
        integer(c_int32_t) :: supports
        real(c_double) :: end_x
        real(c_double) :: end_y
        real(c_double) :: end_z
        real(c_double) :: end_q0
        real(c_double) :: end_q1
        real(c_double) :: end_q2
        real(c_double) :: end_q3
        real(c_double) :: end_dx
        real(c_double) :: end_dy
        real(c_double) :: end_dz
        real(c_double) :: end_tension
        integer(c_int32_t) :: tip_force_frame
        real(c_double) :: tip_force_x
        real(c_double) :: tip_force_y
        real(c_double) :: tip_force_z
        integer(c_int32_t) :: tip_moment_frame
        real(c_double) :: tip_moment_x
        real(c_double) :: tip_moment_y
        real(c_double) :: tip_moment_z
        integer(c_int32_t) :: distributed_force_frame
        real(c_double) :: distributed_force_x
        real(c_double) :: distributed_force_y
        real(c_double) :: distributed_force_z
        integer(c_int32_t) :: distributed_couple_frame
        real(c_double) :: distributed_couple_x
        real(c_double) :: distributed_couple_y
        real(c_double) :: distributed_couple_z
        integer(c_int32_t) :: scheme
        integer(c_int64_t) :: stages
        integer(c_int64_t) :: elements
        real(c_double) :: diameter
    end type rodkit_rod_spec

    ! RodkitContinuationOptions (see rodkit.h).
    type, bind(c) :: rodkit_continuation_options
        integer(c_int32_t) :: method
        integer(c_int64_t) :: anm_order
        real(c_double) :: anm_epsilon
        real(c_double) :: target_lambda
        real(c_double) :: lambda_min
        real(c_double) :: lambda_max
        integer(c_int64_t) :: max_steps
        real(c_double) :: residual_tol
        real(c_double) :: initial_step
        real(c_double) :: min_step
        real(c_double) :: max_step
        integer(c_int32_t) :: detect_bifurcations
        real(c_double) :: bifurcation_tol
        integer(c_int32_t) :: increasing
        type(c_ptr) :: samples
        integer(c_int64_t) :: sample_count
        integer(c_int32_t) :: anm_pade
        type(c_ptr) :: scaling
        integer(c_int64_t) :: scaling_count
    end type rodkit_continuation_options

    ! RodkitBranchProgress (see rodkit.h).
    type, bind(c) :: rodkit_branch_progress
        integer(c_int64_t) :: points
        real(c_double) :: lambda
        real(c_double) :: residual
        real(c_double) :: tip_rotation
        ! Appended for the supercoiling run (-1 and NaN for a rod continuation).
        integer(c_int32_t) :: branch
        real(c_double) :: turns
        real(c_double) :: extension
        real(c_double) :: torque
    end type rodkit_branch_progress

    ! RodkitBranchRecord (see rodkit.h).
    type, bind(c) :: rodkit_branch_record
        real(c_double) :: lambda
        real(c_double) :: residual
        real(c_double) :: step
        real(c_double) :: det_sign
        real(c_double) :: bordered_det_sign
        real(c_double) :: test_function
        integer(c_int64_t) :: newton_iterations
        integer(c_int64_t) :: negative_pivots
        real(c_double) :: tip_x
        real(c_double) :: tip_y
        real(c_double) :: tip_z
        real(c_double) :: tip_rotation
        real(c_double) :: base_force_x
        real(c_double) :: base_force_y
        real(c_double) :: base_force_z
        real(c_double) :: base_moment_x
        real(c_double) :: base_moment_y
        real(c_double) :: base_moment_z
        real(c_double) :: unfolding
        real(c_double) :: end_rotation
    end type rodkit_branch_record

    ! RodkitBranchInfo (see rodkit.h).
    type, bind(c) :: rodkit_branch_info
        integer(c_int64_t) :: records
        integer(c_int64_t) :: bifurcations
        integer(c_int32_t) :: stop
        integer(c_int32_t) :: phase_condition
        integer(c_int64_t) :: state_length
        integer(c_int64_t) :: samples
        integer(c_int64_t) :: missed_samples
        integer(c_int64_t) :: steps
        integer(c_int64_t) :: factorisations
        integer(c_int64_t) :: solves
        integer(c_int64_t) :: residuals
        integer(c_int64_t) :: jacobians
        integer(c_int64_t) :: series_orders
        integer(c_int64_t) :: contact_record
        real(c_double) :: contact_distance
        real(c_double) :: contact_s1
        real(c_double) :: contact_s2
    end type rodkit_branch_info

    ! RodkitBifurcation (see rodkit.h).
    type, bind(c) :: rodkit_bifurcation
        real(c_double) :: lambda
        integer(c_int64_t) :: multiplicity
        real(c_double) :: sigma1
        real(c_double) :: sigma2
        real(c_double) :: sigma3
        integer(c_int32_t) :: det_sign_change
        real(c_double) :: tip_x
        real(c_double) :: tip_y
        real(c_double) :: tip_z
    end type rodkit_bifurcation

    ! RodkitRecordError (see rodkit.h).
    type, bind(c) :: rodkit_record_error
        integer(c_int32_t) :: estimated
        real(c_double) :: tip_position
        real(c_double) :: tip_rotation
        real(c_double) :: base_force
        real(c_double) :: base_moment
        real(c_double) :: scaled
    end type rodkit_record_error

    ! RodkitBifurcationError (see rodkit.h).
    type, bind(c) :: rodkit_bifurcation_error
        integer(c_int32_t) :: estimated
        real(c_double) :: lambda
        real(c_double) :: end_rotation
        real(c_double) :: tip_position
        real(c_double) :: tip_rotation
        real(c_double) :: base_force
        real(c_double) :: base_moment
        real(c_double) :: scaled
    end type rodkit_bifurcation_error

    ! RodkitBifurcationPoint (see rodkit.h).
    type, bind(c) :: rodkit_bifurcation_point
        real(c_double) :: lambda
        real(c_double) :: end_rotation
        integer(c_int64_t) :: record
        integer(c_int64_t) :: multiplicity
        real(c_double) :: sigma1
        real(c_double) :: sigma2
        real(c_double) :: sigma3
        integer(c_int32_t) :: det_sign_change
        integer(c_int32_t) :: test_function_change
        real(c_double) :: tip_x
        real(c_double) :: tip_y
        real(c_double) :: tip_z
    end type rodkit_bifurcation_point

    ! RodkitUnresolvedBifurcation (see rodkit.h).
    type, bind(c) :: rodkit_unresolved_bifurcation
        integer(c_int64_t) :: record_first
        integer(c_int64_t) :: record_last
        real(c_double) :: lambda_first
        real(c_double) :: lambda_last
        integer(c_int32_t) :: det_sign_change
        integer(c_int32_t) :: test_function_change
    end type rodkit_unresolved_bifurcation

    ! RodkitElectrostaticsSpec (see rodkit.h).
    type, bind(c) :: rodkit_electrostatics_spec
        real(c_double) :: line_charge
        real(c_double) :: kappa
        real(c_double) :: a
        real(c_double) :: near_width
        integer(c_int64_t) :: order
    end type rodkit_electrostatics_spec

    ! RodkitEnergyWithin (see rodkit.h).
    type, bind(c) :: rodkit_energy_within
        real(c_double) :: total
        real(c_double) :: near
        real(c_double) :: far
        integer(c_int32_t) :: model
        real(c_double) :: near_width
        integer(c_int64_t) :: order
        real(c_double) :: cutoff
        real(c_double) :: estimate
    end type rodkit_energy_within

    ! RodkitDnaSupercoilSpec (see rodkit.h).
    type, bind(c) :: rodkit_dna_supercoil_spec
        integer(c_int64_t) :: base_pairs
        real(c_double) :: rise
        real(c_double) :: tension
        real(c_double) :: salt
        real(c_double) :: charge_per_length
        real(c_double) :: radius
        real(c_double) :: bending_persistence
        real(c_double) :: twist_persistence
        real(c_double) :: temperature
        real(c_double) :: permittivity
        integer(c_int64_t) :: elements
        integer(c_int64_t) :: stages
        real(c_double) :: cutoff_tolerance
        real(c_double) :: hard_core
        integer(c_int64_t) :: threads
        real(c_double) :: max_turns
        integer(c_int64_t) :: max_steps
        real(c_double) :: residual_tol
        integer(c_int32_t) :: discrete_base_pairs
        integer(c_int32_t) :: end_control
    end type rodkit_dna_supercoil_spec

    ! RodkitSupercoilInfo (see rodkit.h).
    type, bind(c) :: rodkit_supercoil_info
        integer(c_int64_t) :: points
        integer(c_int64_t) :: straight_points
        integer(c_int64_t) :: nodes
        integer(c_int32_t) :: buckled
        real(c_double) :: buckling_turns
        real(c_double) :: buckling_torque
        integer(c_int32_t) :: crossing
        real(c_double) :: crossing_distance
        real(c_double) :: crossing_s1
        real(c_double) :: crossing_s2
        integer(c_int64_t) :: steps
        integer(c_int64_t) :: factorisations
        integer(c_int64_t) :: residuals
        integer(c_int64_t) :: pair_lists
        real(c_double) :: kappa
        real(c_double) :: bjerrum_length
        real(c_double) :: line_charge_squared
        real(c_double) :: cutoff_on
        real(c_double) :: cutoff_off
        real(c_double) :: seconds
        integer(c_int64_t) :: base_pair_charges
        real(c_double) :: hard_core
        integer(c_int32_t) :: hard_core_switched
        real(c_double) :: hard_core_switched_turns
    end type rodkit_supercoil_info

    ! RodkitSupercoilPoint (see rodkit.h).
    type, bind(c) :: rodkit_supercoil_point
        real(c_double) :: turns
        real(c_double) :: extension
        real(c_double) :: torque
        real(c_double) :: tension
        real(c_double) :: twist
        real(c_double) :: writhe
        integer(c_int32_t) :: branch
        real(c_double) :: residual
    end type rodkit_supercoil_point

    ! RodkitSupercoilCurveInfo (see rodkit.h).
    type, bind(c) :: rodkit_supercoil_curve_info
        integer(c_int32_t) :: instability_finding
        real(c_double) :: instability_turns
        real(c_double) :: instability_torque
        integer(c_int32_t) :: coexistence_finding
        real(c_double) :: coexistence_turns
        real(c_double) :: coexistence_torque_straight
        real(c_double) :: coexistence_torque_plectoneme
        real(c_double) :: coexistence_extension_straight
        real(c_double) :: coexistence_extension_plectoneme
        real(c_double) :: coexistence_extension_jump
        integer(c_int32_t) :: plateau_finding
        real(c_double) :: plateau_torque
        real(c_double) :: plateau_torque_min
        real(c_double) :: plateau_torque_max
        real(c_double) :: slope
        real(c_double) :: plateau_turns_from
        real(c_double) :: plateau_turns_to
        integer(c_int64_t) :: plateau_nodes
        integer(c_int32_t) :: superhelix_finding
        real(c_double) :: superhelix_radius
        real(c_double) :: strand_distance
        real(c_double) :: strand_s1
        real(c_double) :: strand_s2
        real(c_double) :: superhelix_turns
    end type rodkit_supercoil_curve_info

    ! RodkitSupercoilCurvePoint (see rodkit.h).
    type, bind(c) :: rodkit_supercoil_curve_point
        real(c_double) :: turns
        real(c_double) :: extension
        real(c_double) :: torque
        real(c_double) :: energy
        integer(c_int32_t) :: kind
        integer(c_int64_t) :: negative_modes
        integer(c_int32_t) :: branch
    end type rodkit_supercoil_curve_point

    ! RodkitEquilibriumSpec (see rodkit.h).
    type, bind(c) :: rodkit_equilibrium_spec
        integer(c_int32_t) :: discrete_base_pairs
        real(c_double) :: cutoff_tolerance
        integer(c_int32_t) :: solver
        real(c_double) :: residual_tol
    end type rodkit_equilibrium_spec

    ! RodkitEquilibrium (see rodkit.h).
    type, bind(c) :: rodkit_equilibrium
        real(c_double) :: turns
        real(c_double) :: extension
        real(c_double) :: torque
        real(c_double) :: tension
        real(c_double) :: twist
        real(c_double) :: writhe
        real(c_double) :: residual
        real(c_double) :: shift
        real(c_double) :: seconds
        integer(c_int64_t) :: newton_iterations
        integer(c_int64_t) :: linear_iterations
        integer(c_int64_t) :: factorisations
        integer(c_int64_t) :: residuals
        integer(c_int64_t) :: pair_lists
        integer(c_int64_t) :: preconditioner_band
    end type rodkit_equilibrium

    ! RodkitElectrostaticEnergy (see rodkit.h).
    type, bind(c) :: rodkit_electrostatic_energy
        real(c_double) :: total
        real(c_double) :: near
        real(c_double) :: far
    end type rodkit_electrostatic_energy

    interface

        ! Deliberately panics inside rodkit's C-boundary guard and returns
        ! RODKIT_STATUS_ERR_INTERNAL, with a last-error message containing
        ! "deliberate panic". It lets a host program verify that a bug inside
        ! rodkit reaches it as a status, never as an abort. The Rust runtime's
        ! default panic hook also prints one line to stderr.
        function rodkit_diagnostic_panic() result(status) bind(c, name="rodkit_diagnostic_panic")
            import :: c_int32_t
            integer(c_int32_t) :: status
        end function rodkit_diagnostic_panic

        ! Human-readable description of a status code (never NULL; static
        ! storage, valid for the life of the program; "unknown rodkit status
        ! code" for codes rodkit does not define). Do not free it. The module
        ! procedure rodkit_status_message(code) returns it as a Fortran string.
        function rodkit_status_string(code) result(message) bind(c, name="rodkit_status_string")
            import :: c_int32_t, c_ptr
            integer(c_int32_t), value :: code
            type(c_ptr) :: message
        end function rodkit_status_string

        ! Message describing the last failure of a rodkit call on the calling
        ! thread, naming the offending argument and value where there is one;
        ! the empty string if the last call succeeded. Never NULL.
        !
        ! The pointer is owned by rodkit (do not free it) and stays valid
        ! until the next rodkit call on the same thread other than
        ! rodkit_last_error_message, rodkit_last_error_copy and
        ! rodkit_status_string. From Fortran prefer the module procedure
        ! rodkit_last_error(), which copies it.
        function rodkit_last_error_message() result(message) bind(c, name="rodkit_last_error_message")
            import :: c_ptr
            type(c_ptr) :: message
        end function rodkit_last_error_message

        ! Copy the last-error message into a caller buffer of `capacity` bytes
        ! (capacity >= 1), always NUL-terminated (the text ends before the
        ! first c_null_char). `length` receives the full message length in
        ! bytes, without the NUL.
        !
        ! Returns RODKIT_STATUS_OK, or RODKIT_STATUS_INFO_TRUNCATED (> 0) when
        ! the message was cut to capacity - 1 bytes. This call leaves the
        ! message unchanged unless it fails itself (capacity < 1). A
        ! character(len=n, kind=c_char) scalar may be passed as `buffer`.
        function rodkit_last_error_copy(buffer, capacity, length) result(status) &
                bind(c, name="rodkit_last_error_copy")
            import :: c_int32_t, c_int64_t, c_char
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: length
            integer(c_int32_t) :: status
        end function rodkit_last_error_copy

        ! Fill `spec` with its defaults: every field NaN (unset). Set all of them.
        function rodkit_thin_tube_spec_default(spec) result(status) &
                bind(c, name="rodkit_thin_tube_spec_default")
            import :: c_int32_t, rodkit_thin_tube_spec
            type(rodkit_thin_tube_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_spec_default

        ! Helix angle alpha = atan(tau0*R) of the reinforcement at the mid
        ! surface, in radians from the tube axis. Validates `spec` like the
        ! functions below. On failure `alpha` is not written.
        function rodkit_thin_tube_helix_angle(spec, alpha) result(status) &
                bind(c, name="rodkit_thin_tube_helix_angle")
            import :: c_int32_t, c_double, rodkit_thin_tube_spec
            type(rodkit_thin_tube_spec), intent(in) :: spec
            real(c_double), intent(out) :: alpha
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_helix_angle

        ! Linear coupling stiffness K (physics.md 1.4), symmetric positive
        ! definite: (F, T, 2 pi R^2 p) = K (eps, psi, eps_theta), with eps the
        ! axial strain, psi the twist per length, eps_theta the mid-surface
        ! hoop strain, F the axial force carried by the wall (open ends), T
        ! the torque and p the inner pressure.
        !
        ! `k` receives the 3x3 matrix column-major with leading dimension
        ! ldk >= 3: declare it k(ldk, 3) (at least 2*ldk + 3 doubles) and
        ! K(i, j) is k(i, j). Rows 4..ldk are left unchanged.
        function rodkit_thin_tube_coupling_stiffness(spec, k, ldk) result(status) &
                bind(c, name="rodkit_thin_tube_coupling_stiffness")
            import :: c_int32_t, c_int64_t, c_double, rodkit_thin_tube_spec
            type(rodkit_thin_tube_spec), intent(in) :: spec
            real(c_double), intent(inout) :: k(*)
            integer(c_int64_t), value :: ldk
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_coupling_stiffness

        ! Condensed stretch-twist law at zero pressure (inflation eliminated):
        ! (F, T) = [[S, g], [g, C]] (eps, psi), the hemitropic rod coupling of
        ! physics.md 2.2. `s` receives the 2x2 matrix column-major with
        ! leading dimension lds >= 2: declare it s(lds, 2); S = s(1,1),
        ! g = s(1,2) = s(2,1), C = s(2,2). Rows 3..lds are left unchanged.
        function rodkit_thin_tube_stretch_twist(spec, s, lds) result(status) &
                bind(c, name="rodkit_thin_tube_stretch_twist")
            import :: c_int32_t, c_int64_t, c_double, rodkit_thin_tube_spec
            type(rodkit_thin_tube_spec), intent(in) :: spec
            real(c_double), intent(inout) :: s(*)
            integer(c_int64_t), value :: lds
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_stretch_twist

        ! The section as a hemitropic rod (physics.md 2.2), thin-walled beam
        ! theory: 6x6 stiffness in k(ldk, 6), strains ordered (u1, u2, u3,
        ! v1, v2, v3): bending k(1,1) = k(2,2), twist k(3,3), shear k(4,4) =
        ! k(5,5), stretch k(6,6), twist-stretch g = k(3,6), bend-shear
        ! c2 = k(1,4) = k(2,5) = -g/2.
        function rodkit_thin_tube_rod_stiffness(spec, k, ldk) result(status) &
                bind(c, name="rodkit_thin_tube_rod_stiffness")
            import :: c_int32_t, c_int64_t, c_double, rodkit_thin_tube_spec
            type(rodkit_thin_tube_spec), intent(in) :: spec
            real(c_double), intent(inout) :: k(*)
            integer(c_int64_t), value :: ldk
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_rod_stiffness

        ! Response of the free tube (T = 0, p = 0) to an axial force, and
        ! whether it over- or unwinds (decided by the condensed coupling g,
        ! not by K(1,2) alone).
        function rodkit_thin_tube_free_response(spec, response) result(status) &
                bind(c, name="rodkit_thin_tube_free_response")
            import :: c_int32_t, rodkit_thin_tube_spec, rodkit_free_tube_response
            type(rodkit_thin_tube_spec), intent(in) :: spec
            type(rodkit_free_tube_response), intent(out) :: response
            integer(c_int32_t) :: status
        end function rodkit_thin_tube_free_response

        ! Library version (semantic versioning, from Cargo.toml). On failure
        ! nothing is written.
        function rodkit_version(major, minor, patch) result(status) bind(c, name="rodkit_version")
            import :: c_int32_t
            integer(c_int32_t), intent(out) :: major
            integer(c_int32_t), intent(out) :: minor
            integer(c_int32_t), intent(out) :: patch
            integer(c_int32_t) :: status
        end function rodkit_version

        ! ABI version of the loaded library; equals RODKIT_ABI_VERSION of the
        ! header (and of this module) it was built with. It changes only when
        ! the binary interface does.
        function rodkit_library_abi_version() result(version) bind(c, name="rodkit_library_abi_version")
            import :: c_int32_t
            integer(c_int32_t) :: version
        end function rodkit_library_abi_version


        ! Fit the thin-wall (E1, E2, G12) of a tube (R, helix angle, t, nu12) to
        ! the stretch-twist law [[S, g], [g, C]]; also the thick-wall value.
        function rodkit_dna_fit_thin_wall(stretch, twist, coupling, mid_radius, helix_angle, thickness, nu12, out) &
                result(status) bind(c, name="rodkit_dna_fit_thin_wall")
            import :: c_int32_t, c_double, rodkit_dna_fit
            real(c_double), value :: stretch, twist, coupling, mid_radius, helix_angle, thickness, nu12
            type(rodkit_dna_fit), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_dna_fit_thin_wall

        ! ---------------------------------------------------------------------
        ! Tube solver (physics.md 1.2-1.5): see rodkit.h for the full contracts.
        ! ---------------------------------------------------------------------

        ! Fill spec with defaults: law unset, compressible, tau0 = 0, every
        ! constant NaN, no fibres, fibre hands +1 and -1.
        function rodkit_wall_material_spec_default(spec) result(status) &
                bind(c, name="rodkit_wall_material_spec_default")
            import :: c_int32_t, rodkit_wall_material_spec
            type(rodkit_wall_material_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_wall_material_spec_default

        ! Fill spec with defaults: radii NaN, material default, model Auto,
        ! rel_tol 1e-8, adaptive grid.
        function rodkit_tube_spec_default(spec) result(status) bind(c, name="rodkit_tube_spec_default")
            import :: c_int32_t, rodkit_tube_spec
            type(rodkit_tube_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_tube_spec_default

        ! Fill loading with the unloaded state (stretch 1, twist 0, no
        ! pressure, open ends).
        function rodkit_tube_loading_default(loading) result(status) bind(c, name="rodkit_tube_loading_default")
            import :: c_int32_t, rodkit_tube_loading
            type(rodkit_tube_loading), intent(out) :: loading
            integer(c_int32_t) :: status
        end function rodkit_tube_loading_default

        ! Validate spec and create a tube; out receives the handle (free it
        ! with rodkit_tube_free) or c_null_ptr on failure.
        function rodkit_tube_new(spec, out) result(status) bind(c, name="rodkit_tube_new")
            import :: c_int32_t, c_ptr, rodkit_tube_spec
            type(rodkit_tube_spec), intent(in) :: spec
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_tube_new

        ! Destroy a tube (c_null_ptr accepted).
        subroutine rodkit_tube_free(tube) bind(c, name="rodkit_tube_free")
            import :: c_ptr
            type(c_ptr), value :: tube
        end subroutine rodkit_tube_free

        ! Equilibrium of tube under loading.
        function rodkit_tube_solve(tube, loading, out) result(status) bind(c, name="rodkit_tube_solve")
            import :: c_int32_t, c_ptr, rodkit_tube_loading, rodkit_tube_state
            type(c_ptr), value :: tube
            type(rodkit_tube_loading), intent(in) :: loading
            type(rodkit_tube_state), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_tube_solve

        ! Stresses through the wall; capacity 0 is a size query (count only,
        ! pass any arrays), else each array needs capacity >= count.
        function rodkit_tube_profile(tube, loading, capacity, reference_radius, radius, sigma_rr, sigma_tt, &
                sigma_zz, sigma_tz, count) result(status) bind(c, name="rodkit_tube_profile")
            import :: c_int32_t, c_int64_t, c_double, c_ptr, rodkit_tube_loading
            type(c_ptr), value :: tube
            type(rodkit_tube_loading), intent(in) :: loading
            integer(c_int64_t), value :: capacity
            real(c_double), intent(inout) :: reference_radius(*), radius(*), sigma_rr(*), sigma_tt(*), &
                sigma_zz(*), sigma_tz(*)
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_tube_profile

        ! Equilibria along count loadings of the same kind into states; progress
        ! (c_funloc of a bind(c) function returning integer(c_int32_t), taking
        ! (type(rodkit_progress), intent(in) and type(c_ptr), value), or
        ! c_null_funptr) may stop the sweep: RODKIT_STATUS_INFO_CANCELLED.
        function rodkit_tube_sweep(tube, loadings, count, states, progress, user_data, completed) result(status) &
                bind(c, name="rodkit_tube_sweep")
            import :: c_int32_t, c_int64_t, c_ptr, c_funptr, rodkit_tube_loading, rodkit_tube_state
            type(c_ptr), value :: tube
            type(rodkit_tube_loading), intent(in) :: loadings(*)
            integer(c_int64_t), value :: count
            type(rodkit_tube_state), intent(inout) :: states(*)
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            integer(c_int64_t), intent(out) :: completed
            integer(c_int32_t) :: status
        end function rodkit_tube_sweep

        ! Linear coupling stiffness K (3x3, column-major, k(ldk, 3)) about rest,
        ! inner-radius variables; error_estimate its relative error estimate.
        function rodkit_tube_coupling_stiffness(tube, k, ldk, error_estimate) result(status) &
                bind(c, name="rodkit_tube_coupling_stiffness")
            import :: c_int32_t, c_int64_t, c_double, c_ptr
            type(c_ptr), value :: tube
            real(c_double), intent(inout) :: k(*)
            integer(c_int64_t), value :: ldk
            real(c_double), intent(out) :: error_estimate
            integer(c_int32_t) :: status
        end function rodkit_tube_coupling_stiffness

        ! The section as a rod: [[S, g], [g, C]] in s(lds, 2).
        function rodkit_tube_stretch_twist(tube, s, lds) result(status) bind(c, name="rodkit_tube_stretch_twist")
            import :: c_int32_t, c_int64_t, c_double, c_ptr
            type(c_ptr), value :: tube
            real(c_double), intent(inout) :: s(*)
            integer(c_int64_t), value :: lds
            integer(c_int32_t) :: status
        end function rodkit_tube_stretch_twist

        ! The section as a hemitropic rod: 6x6 stiffness in k(ldk, 6), same
        ! order as rodkit_thin_tube_rod_stiffness; stretch-twist block from
        ! the thick theory, bending and shear layer by layer.
        function rodkit_tube_rod_stiffness(tube, k, ldk, error_estimate) result(status) &
                bind(c, name="rodkit_tube_rod_stiffness")
            import :: c_int32_t, c_int64_t, c_double, c_ptr
            type(c_ptr), value :: tube
            real(c_double), intent(inout) :: k(*)
            integer(c_int64_t), value :: ldk
            real(c_double), intent(out) :: error_estimate
            integer(c_int32_t) :: status
        end function rodkit_tube_rod_stiffness

        ! ---------------------------------------------------------------------
        ! Cosserat rods and continuation (see rodkit.h for every function).
        ! Handles (rod, branch) are type(c_ptr). The progress callback is
        ! c_funloc of a bind(c) function taking (type(rodkit_branch_progress),
        ! intent(in) and type(c_ptr), value) and returning
        ! integer(c_int32_t) (non-zero stops), or c_null_funptr. x0 of
        ! rodkit_rod_continue: pass a state (e.g. rodkit_rod_straight_state).
        ! ---------------------------------------------------------------------
        function rodkit_rod_spec_default(spec) result(status) &
                bind(c, name="rodkit_rod_spec_default")
            import :: c_int32_t, rodkit_rod_spec
            type(rodkit_rod_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_rod_spec_default

        function rodkit_continuation_options_default(options) result(status) &
                bind(c, name="rodkit_continuation_options_default")
            import :: c_int32_t, rodkit_continuation_options
            type(rodkit_continuation_options), intent(out) :: options
            integer(c_int32_t) :: status
        end function rodkit_continuation_options_default

        function rodkit_rod_new(spec, out) result(status) &
                bind(c, name="rodkit_rod_new")
            import :: c_int32_t, c_ptr, rodkit_rod_spec
            type(rodkit_rod_spec), intent(in) :: spec
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_rod_new

        function rodkit_rod_new_general(spec, stiffness, ldk, out) result(status) &
                bind(c, name="rodkit_rod_new_general")
            import :: c_double, c_int32_t, c_int64_t, c_ptr, rodkit_rod_spec
            type(rodkit_rod_spec), intent(in) :: spec
            real(c_double), intent(in) :: stiffness(*)
            integer(c_int64_t), value :: ldk
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_rod_new_general

        subroutine rodkit_rod_free(rod) &
                bind(c, name="rodkit_rod_free")
            import :: c_ptr
            type(c_ptr), value :: rod
        end subroutine rodkit_rod_free

        function rodkit_rod_set_target_rotation(rod, phi) result(status) &
                bind(c, name="rodkit_rod_set_target_rotation")
            import :: c_double, c_int32_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), value :: phi
            integer(c_int32_t) :: status
        end function rodkit_rod_set_target_rotation

        function rodkit_rod_unknowns(rod, n) result(status) &
                bind(c, name="rodkit_rod_unknowns")
            import :: c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            integer(c_int64_t), intent(out) :: n
            integer(c_int32_t) :: status
        end function rodkit_rod_unknowns

        function rodkit_rod_straight_state(rod, x, n) result(status) &
                bind(c, name="rodkit_rod_straight_state")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(inout) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int32_t) :: status
        end function rodkit_rod_straight_state

        function rodkit_rod_continue_to_tolerance(rod, tolerance, lambda0, options, progress, user_data, &
                rod_out, out) result(status) bind(c, name="rodkit_rod_continue_to_tolerance")
            import :: c_double, c_funptr, c_int32_t, c_ptr, rodkit_continuation_options
            type(c_ptr), value :: rod
            real(c_double), value :: tolerance
            real(c_double), value :: lambda0
            type(rodkit_continuation_options), intent(in) :: options
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            type(c_ptr), intent(out) :: rod_out
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_rod_continue_to_tolerance

        function rodkit_branch_error_estimates(branch, rod, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_error_estimates")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_record_error
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            type(rodkit_record_error), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_error_estimates

        function rodkit_branch_bifurcation_errors(branch, rod, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_bifurcation_errors")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_bifurcation_error
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            type(rodkit_bifurcation_error), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_bifurcation_errors

        function rodkit_branch_kirchhoff_differences(branch, rod, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_kirchhoff_differences")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_record_error
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            type(rodkit_record_error), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_kirchhoff_differences

        function rodkit_rod_continue(rod, x0, n, lambda0, options, progress, user_data, out) result(status) &
                bind(c, name="rodkit_rod_continue")
            import :: c_double, c_funptr, c_int32_t, c_int64_t, c_ptr, rodkit_continuation_options
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: x0(*)
            integer(c_int64_t), value :: n
            real(c_double), value :: lambda0
            type(rodkit_continuation_options), intent(in) :: options
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_rod_continue

        function rodkit_branch_resume(rod, branch, options, progress, user_data, out) result(status) &
                bind(c, name="rodkit_branch_resume")
            import :: c_funptr, c_int32_t, c_ptr, rodkit_continuation_options
            type(c_ptr), value :: rod
            type(c_ptr), value :: branch
            type(rodkit_continuation_options), intent(in) :: options
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_branch_resume

        function rodkit_branch_switch(rod, branch, index, direction, first_step, options, progress, user_data, out) result(status) &
                bind(c, name="rodkit_branch_switch")
            import :: c_double, c_funptr, c_int32_t, c_int64_t, c_ptr, rodkit_continuation_options
            type(c_ptr), value :: rod
            type(c_ptr), value :: branch
            integer(c_int64_t), value :: index
            integer(c_int64_t), value :: direction
            real(c_double), value :: first_step
            type(rodkit_continuation_options), intent(in) :: options
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_branch_switch

        subroutine rodkit_branch_free(branch) &
                bind(c, name="rodkit_branch_free")
            import :: c_ptr
            type(c_ptr), value :: branch
        end subroutine rodkit_branch_free

        function rodkit_branch_summary(branch, info) result(status) &
                bind(c, name="rodkit_branch_summary")
            import :: c_int32_t, c_ptr, rodkit_branch_info
            type(c_ptr), value :: branch
            type(rodkit_branch_info), intent(out) :: info
            integer(c_int32_t) :: status
        end function rodkit_branch_summary

        function rodkit_branch_records(branch, records, capacity, count) result(status) &
                bind(c, name="rodkit_branch_records")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_branch_record
            type(c_ptr), value :: branch
            type(rodkit_branch_record), intent(inout) :: records(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_records

        function rodkit_branch_samples(branch, samples, capacity, count) result(status) &
                bind(c, name="rodkit_branch_samples")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_branch_record
            type(c_ptr), value :: branch
            type(rodkit_branch_record), intent(inout) :: samples(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_samples

        function rodkit_branch_sample_state(branch, sample, x, n) result(status) &
                bind(c, name="rodkit_branch_sample_state")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            integer(c_int64_t), value :: sample
            real(c_double), intent(inout) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int32_t) :: status
        end function rodkit_branch_sample_state

        function rodkit_branch_bifurcations(branch, rod, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_bifurcations")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_bifurcation
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            type(rodkit_bifurcation), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_bifurcations

        function rodkit_branch_bifurcation_points(branch, rod, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_bifurcation_points")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_bifurcation_point
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            type(rodkit_bifurcation_point), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_bifurcation_points

        function rodkit_branch_bifurcation_state(branch, index, x, n) result(status) &
                bind(c, name="rodkit_branch_bifurcation_state")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            integer(c_int64_t), value :: index
            real(c_double), intent(inout) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int32_t) :: status
        end function rodkit_branch_bifurcation_state

        function rodkit_branch_unresolved(branch, out, capacity, count) result(status) &
                bind(c, name="rodkit_branch_unresolved")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_unresolved_bifurcation
            type(c_ptr), value :: branch
            type(rodkit_unresolved_bifurcation), intent(inout) :: out(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_branch_unresolved

        function rodkit_branch_state(branch, record, x, n) result(status) &
                bind(c, name="rodkit_branch_state")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            integer(c_int64_t), value :: record
            real(c_double), intent(inout) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int32_t) :: status
        end function rodkit_branch_state

        function rodkit_branch_positions(branch, rod, record, xyz, ld, nodes) result(status) &
                bind(c, name="rodkit_branch_positions")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            integer(c_int64_t), value :: record
            real(c_double), intent(inout) :: xyz(*)
            integer(c_int64_t), value :: ld
            integer(c_int64_t), value :: nodes
            integer(c_int32_t) :: status
        end function rodkit_branch_positions

        ! Files for other tools: the shapes of n chosen records as legacy VTK
        ! polydata (cell data lambda, end_rotation) or the records as CSV; a
        ! supercoiling path's shapes (cell data turns, extension, torque,
        ! writhe) or points likewise. `path` is a NUL-terminated file name
        ! (trim(name)//c_null_char); nothing is written on failure
        ! (RODKIT_STATUS_ERR_IO names the path and the reason).
        function rodkit_branch_write_vtk(branch, rod, records, n, path) result(status) &
                bind(c, name="rodkit_branch_write_vtk")
            import :: c_char, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            integer(c_int64_t), intent(in) :: records(*)
            integer(c_int64_t), value :: n
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_branch_write_vtk

        function rodkit_branch_write_csv(branch, rod, path) result(status) &
                bind(c, name="rodkit_branch_write_csv")
            import :: c_char, c_int32_t, c_ptr
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_branch_write_csv

        ! The dense-output samples (RodkitContinuationOptions.samples) of a
        ! branch likewise: n chosen samples' shapes as VTK, all as CSV; a
        ! branch without samples gives RODKIT_STATUS_ERR_OUT_OF_RANGE.
        function rodkit_branch_write_samples_vtk(branch, rod, samples, n, path) result(status) &
                bind(c, name="rodkit_branch_write_samples_vtk")
            import :: c_char, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            integer(c_int64_t), intent(in) :: samples(*)
            integer(c_int64_t), value :: n
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_branch_write_samples_vtk

        function rodkit_branch_write_samples_csv(branch, rod, path) result(status) &
                bind(c, name="rodkit_branch_write_samples_csv")
            import :: c_char, c_int32_t, c_ptr
            type(c_ptr), value :: branch
            type(c_ptr), value :: rod
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_branch_write_samples_csv

        function rodkit_supercoil_write_vtk(run, points, n, path) result(status) &
                bind(c, name="rodkit_supercoil_write_vtk")
            import :: c_char, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: run
            integer(c_int64_t), intent(in) :: points(*)
            integer(c_int64_t), value :: n
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_supercoil_write_vtk

        function rodkit_supercoil_write_csv(run, path) result(status) &
                bind(c, name="rodkit_supercoil_write_csv")
            import :: c_char, c_int32_t, c_ptr
            type(c_ptr), value :: run
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_supercoil_write_csv

        ! A tube sweep as CSV: the count loadings and the states
        ! rodkit_tube_sweep returned (its `completed`), the header's units
        ! in the caller's length and force units (e.g. 'nm'//c_null_char,
        ! 'pN'//c_null_char).
        function rodkit_tube_sweep_write_csv(loadings, states, count, length_unit, force_unit, path) &
                result(status) bind(c, name="rodkit_tube_sweep_write_csv")
            import :: c_char, c_int32_t, c_int64_t, rodkit_tube_loading, rodkit_tube_state
            type(rodkit_tube_loading), intent(in) :: loadings(*)
            type(rodkit_tube_state), intent(in) :: states(*)
            integer(c_int64_t), value :: count
            character(kind=c_char), intent(in) :: length_unit(*)
            character(kind=c_char), intent(in) :: force_unit(*)
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int32_t) :: status
        end function rodkit_tube_sweep_write_csv

        function rodkit_rod_node_positions(rod, s, capacity, count) result(status) &
                bind(c, name="rodkit_rod_node_positions")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(inout) :: s(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_rod_node_positions

        function rodkit_rod_node_state(rod, x, n, node, position, quaternion, force, moment) result(status) &
                bind(c, name="rodkit_rod_node_state")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int64_t), value :: node
            real(c_double), intent(inout) :: position(*)
            real(c_double), intent(inout) :: quaternion(*)
            real(c_double), intent(inout) :: force(*)
            real(c_double), intent(inout) :: moment(*)
            integer(c_int32_t) :: status
        end function rodkit_rod_node_state

        function rodkit_rod_node_rotation(rod, x, n, node, rotation) result(status) &
                bind(c, name="rodkit_rod_node_rotation")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: x(*)
            integer(c_int64_t), value :: n
            integer(c_int64_t), value :: node
            real(c_double), intent(inout) :: rotation(*)
            integer(c_int32_t) :: status
        end function rodkit_rod_node_rotation

        function rodkit_rod_residual(rod, x, n, lambda, r) result(status) &
                bind(c, name="rodkit_rod_residual")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: x(*)
            integer(c_int64_t), value :: n
            real(c_double), value :: lambda
            real(c_double), intent(inout) :: r(*)
            integer(c_int32_t) :: status
        end function rodkit_rod_residual

        function rodkit_rod_jacobian_pattern(rod, col_ptr, row_idx, capacity, nnz) result(status) &
                bind(c, name="rodkit_rod_jacobian_pattern")
            import :: c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            integer(c_int64_t), intent(inout) :: col_ptr(*)
            integer(c_int64_t), intent(inout) :: row_idx(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: nnz
            integer(c_int32_t) :: status
        end function rodkit_rod_jacobian_pattern

        function rodkit_rod_jacobian(rod, x, n, lambda, values, nnz, d_lambda) result(status) &
                bind(c, name="rodkit_rod_jacobian")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: x(*)
            integer(c_int64_t), value :: n
            real(c_double), value :: lambda
            real(c_double), intent(inout) :: values(*)
            integer(c_int64_t), value :: nnz
            real(c_double), intent(inout) :: d_lambda(*)
            integer(c_int32_t) :: status
        end function rodkit_rod_jacobian

        function rodkit_rod_rhs(rod, y, lambda, dy) result(status) &
                bind(c, name="rodkit_rod_rhs")
            import :: c_double, c_int32_t, c_ptr
            type(c_ptr), value :: rod
            real(c_double), intent(in) :: y(*)
            real(c_double), value :: lambda
            real(c_double), intent(inout) :: dy(*)
            integer(c_int32_t) :: status
        end function rodkit_rod_rhs
        function rodkit_electrostatics_spec_default(spec) result(status) &
                bind(c, name="rodkit_electrostatics_spec_default")
            import :: c_int32_t, rodkit_electrostatics_spec
            type(rodkit_electrostatics_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_electrostatics_spec_default

        function rodkit_curve_electrostatic_energy(s, xyz, ldx, tangents, ldt, nodes, closed, spec, energy) result(status) &
                bind(c, name="rodkit_curve_electrostatic_energy")
            import :: c_double, c_int32_t, c_int64_t, rodkit_electrostatics_spec, rodkit_electrostatic_energy
            real(c_double), intent(in) :: s(*)
            real(c_double), intent(in) :: xyz(*)
            integer(c_int64_t), value :: ldx
            real(c_double), intent(in) :: tangents(*)
            integer(c_int64_t), value :: ldt
            integer(c_int64_t), value :: nodes
            integer(c_int32_t), value :: closed
            type(rodkit_electrostatics_spec), intent(in) :: spec
            type(rodkit_electrostatic_energy), intent(out) :: energy
            integer(c_int32_t) :: status
        end function rodkit_curve_electrostatic_energy

        function rodkit_curve_base_pair_energy(s, xyz, ldx, tangents, ldt, nodes, closed, spec, spacing, energy) result(status) &
                bind(c, name="rodkit_curve_base_pair_energy")
            import :: c_double, c_int32_t, c_int64_t, rodkit_electrostatics_spec
            real(c_double), intent(in) :: s(*)
            real(c_double), intent(in) :: xyz(*)
            integer(c_int64_t), value :: ldx
            real(c_double), intent(in) :: tangents(*)
            integer(c_int64_t), value :: ldt
            integer(c_int64_t), value :: nodes
            integer(c_int32_t), value :: closed
            type(rodkit_electrostatics_spec), intent(in) :: spec
            real(c_double), value :: spacing
            real(c_double), intent(out) :: energy
            integer(c_int32_t) :: status
        end function rodkit_curve_base_pair_energy

        function rodkit_curve_writhe(s, xyz, ldx, tangents, ldt, nodes, closed, order, writhe_out) result(status) &
                bind(c, name="rodkit_curve_writhe")
            import :: c_double, c_int32_t, c_int64_t
            real(c_double), intent(in) :: s(*)
            real(c_double), intent(in) :: xyz(*)
            integer(c_int64_t), value :: ldx
            real(c_double), intent(in) :: tangents(*)
            integer(c_int64_t), value :: ldt
            integer(c_int64_t), value :: nodes
            integer(c_int32_t), value :: closed
            integer(c_int64_t), value :: order
            real(c_double), intent(out) :: writhe_out
            integer(c_int32_t) :: status
        end function rodkit_curve_writhe


        function rodkit_curve_electrostatic_energy_within(s, xyz, ldx, tangents, ldt, nodes, closed, spec, tolerance, out) &
                result(status) &
                bind(c, name="rodkit_curve_electrostatic_energy_within")
            import :: c_double, c_int32_t, c_int64_t, rodkit_electrostatics_spec, rodkit_energy_within
            real(c_double), intent(in) :: s(*)
            real(c_double), intent(in) :: xyz(*)
            integer(c_int64_t), value :: ldx
            real(c_double), intent(in) :: tangents(*)
            integer(c_int64_t), value :: ldt
            integer(c_int64_t), value :: nodes
            integer(c_int32_t), value :: closed
            type(rodkit_electrostatics_spec), intent(in) :: spec
            real(c_double), value :: tolerance
            type(rodkit_energy_within), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_curve_electrostatic_energy_within

        function rodkit_dna_supercoil_spec_default(spec) result(status) &
                bind(c, name="rodkit_dna_supercoil_spec_default")
            import :: c_int32_t, rodkit_dna_supercoil_spec
            type(rodkit_dna_supercoil_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_dna_supercoil_spec_default

        function rodkit_dna_supercoil_run(spec, out) result(status) &
                bind(c, name="rodkit_dna_supercoil_run")
            import :: c_int32_t, c_ptr, rodkit_dna_supercoil_spec
            type(rodkit_dna_supercoil_spec), intent(in) :: spec
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_dna_supercoil_run

        ! progress: c_funloc of a bind(c) function taking
        ! (type(rodkit_branch_progress), intent(in) and type(c_ptr), value)
        ! and returning integer(c_int32_t) (non-zero stops the run:
        ! RODKIT_STATUS_INFO_CANCELLED, the path so far in out), or
        ! c_null_funptr.
        function rodkit_dna_supercoil_run_with(spec, progress, user_data, out) result(status) &
                bind(c, name="rodkit_dna_supercoil_run_with")
            import :: c_funptr, c_int32_t, c_ptr, rodkit_dna_supercoil_spec
            type(rodkit_dna_supercoil_spec), intent(in) :: spec
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            type(c_ptr), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_dna_supercoil_run_with

        ! Continue, in place, a run its callback stopped.
        function rodkit_supercoil_resume(run, progress, user_data) result(status) &
                bind(c, name="rodkit_supercoil_resume")
            import :: c_funptr, c_int32_t, c_ptr
            type(c_ptr), value :: run
            type(c_funptr), value :: progress
            type(c_ptr), value :: user_data
            integer(c_int32_t) :: status
        end function rodkit_supercoil_resume

        function rodkit_supercoil_stop(run, stop) result(status) &
                bind(c, name="rodkit_supercoil_stop")
            import :: c_int32_t, c_ptr
            type(c_ptr), value :: run
            integer(c_int32_t), intent(out) :: stop
            integer(c_int32_t) :: status
        end function rodkit_supercoil_stop

        ! Why a run failed partway (RODKIT_SUPERCOIL_STOP_FAILED): `error`
        ! receives the error's negative status (0 when the run did not fail)
        ! and `buffer` (capacity >= 1 bytes) its message, always
        ! NUL-terminated (empty when it did not fail); `length` the full
        ! message length in bytes. RODKIT_STATUS_INFO_TRUNCATED when the
        ! message was cut to capacity - 1 bytes. A character(len=n,
        ! kind=c_char) scalar may be passed as `buffer`.
        function rodkit_supercoil_failure(run, error, buffer, capacity, length) result(status) &
                bind(c, name="rodkit_supercoil_failure")
            import :: c_int32_t, c_int64_t, c_char, c_ptr
            type(c_ptr), value :: run
            integer(c_int32_t), intent(out) :: error
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: length
            integer(c_int32_t) :: status
        end function rodkit_supercoil_failure

        subroutine rodkit_supercoil_free(run) &
                bind(c, name="rodkit_supercoil_free")
            import :: c_ptr
            type(c_ptr), value :: run
        end subroutine rodkit_supercoil_free

        function rodkit_supercoil_summary(run, info) result(status) &
                bind(c, name="rodkit_supercoil_summary")
            import :: c_int32_t, c_ptr, rodkit_supercoil_info
            type(c_ptr), value :: run
            type(rodkit_supercoil_info), intent(out) :: info
            integer(c_int32_t) :: status
        end function rodkit_supercoil_summary

        function rodkit_supercoil_points(run, points, capacity, count) result(status) &
                bind(c, name="rodkit_supercoil_points")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_supercoil_point
            type(c_ptr), value :: run
            type(rodkit_supercoil_point), intent(inout) :: points(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_supercoil_points

        function rodkit_supercoil_positions(run, point, xyz, ld, nodes) result(status) &
                bind(c, name="rodkit_supercoil_positions")
            import :: c_double, c_int32_t, c_int64_t, c_ptr
            type(c_ptr), value :: run
            integer(c_int64_t), value :: point
            real(c_double), intent(inout) :: xyz(*)
            integer(c_int64_t), value :: ld
            integer(c_int64_t), value :: nodes
            integer(c_int32_t) :: status
        end function rodkit_supercoil_positions

        function rodkit_supercoil_curve_summary(run, out) result(status) &
                bind(c, name="rodkit_supercoil_curve_summary")
            import :: c_int32_t, c_ptr, rodkit_supercoil_curve_info
            type(c_ptr), value :: run
            type(rodkit_supercoil_curve_info), intent(out) :: out
            integer(c_int32_t) :: status
        end function rodkit_supercoil_curve_summary

        function rodkit_supercoil_curve_points(run, points, capacity, count) result(status) &
                bind(c, name="rodkit_supercoil_curve_points")
            import :: c_int32_t, c_int64_t, c_ptr, rodkit_supercoil_curve_point
            type(c_ptr), value :: run
            type(rodkit_supercoil_curve_point), intent(inout) :: points(*)
            integer(c_int64_t), value :: capacity
            integer(c_int64_t), intent(out) :: count
            integer(c_int32_t) :: status
        end function rodkit_supercoil_curve_points

        function rodkit_equilibrium_spec_default(spec) result(status) &
                bind(c, name="rodkit_equilibrium_spec_default")
            import :: c_int32_t, rodkit_equilibrium_spec
            type(rodkit_equilibrium_spec), intent(out) :: spec
            integer(c_int32_t) :: status
        end function rodkit_equilibrium_spec_default

        ! xyz must be an array here (C accepts NULL to skip the shape).
        function rodkit_supercoil_solve_point(run, point, spec, out, xyz, ld, nodes) result(status) &
                bind(c, name="rodkit_supercoil_solve_point")
            import :: c_double, c_int32_t, c_int64_t, c_ptr, rodkit_equilibrium_spec, rodkit_equilibrium
            type(c_ptr), value :: run
            integer(c_int64_t), value :: point
            type(rodkit_equilibrium_spec), intent(in) :: spec
            type(rodkit_equilibrium), intent(out) :: out
            real(c_double), intent(inout) :: xyz(*)
            integer(c_int64_t), value :: ld
            integer(c_int64_t), value :: nodes
            integer(c_int32_t) :: status
        end function rodkit_supercoil_solve_point

    end interface

contains

    ! Description of a status code as a Fortran string (a copy of
    ! rodkit_status_string(code)); e.g. "success" for RODKIT_STATUS_OK.
    function rodkit_status_message(code) result(message)
        integer(c_int32_t), intent(in) :: code
        character(len=:), allocatable :: message
        message = c_string_to_fortran(rodkit_status_string(code))
    end function rodkit_status_message

    ! The last-error message of the calling thread as a Fortran string (a
    ! copy: it stays valid whatever rodkit is called next); "" if the last
    ! rodkit call succeeded. Obtained with rodkit_last_error_copy: a size
    ! query, then a copy into a buffer of exactly the right size. Does not
    ! change the message.
    function rodkit_last_error() result(message)
        character(len=:), allocatable :: message
        character(len=1, kind=c_char) :: probe
        character(len=:, kind=c_char), allocatable :: buffer
        integer(c_int64_t) :: length, copied
        integer(c_int32_t) :: status
        integer :: n, i

        length = 0
        status = rodkit_last_error_copy(probe, 1_c_int64_t, length)
        if (status < 0 .or. length <= 0) then
            message = ""
            if (status < 0) message = "rodkit_last_error: could not read the message"
            return
        end if
        allocate(character(len=int(length) + 1, kind=c_char) :: buffer)
        status = rodkit_last_error_copy(buffer, length + 1, copied)
        if (status < 0) then
            message = "rodkit_last_error: could not read the message"
            return
        end if
        ! The text ends at the first NUL (the copy is always NUL-terminated).
        n = index(buffer, c_null_char) - 1
        if (n < 0) n = len(buffer)
        allocate(character(len=n) :: message)
        do i = 1, n
            message(i:i) = buffer(i:i)
        end do
    end function rodkit_last_error

    ! Copy of a NUL-terminated C string owned by rodkit ("" for NULL).
    function c_string_to_fortran(ptr) result(text)
        type(c_ptr), intent(in) :: ptr
        character(len=:), allocatable :: text
        character(kind=c_char), pointer :: chars(:)
        integer :: n, i

        if (.not. c_associated(ptr)) then
            text = ""
            return
        end if
        call c_f_pointer(ptr, chars, [huge(0)])
        n = 0
        do while (chars(n + 1) /= c_null_char)
            n = n + 1
        end do
        allocate(character(len=n) :: text)
        do i = 1, n
            text(i:i) = chars(i)
        end do
    end function c_string_to_fortran

end module rodkit
