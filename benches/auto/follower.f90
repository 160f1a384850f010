!---------------------------------------------------------------------------------------------------
! AUTO-07p problems "follower" and "dead": clamped-free Cosserat rod (physics.md §2.1, quaternion
! form, 13 ODEs) with a follower tip force kept perpendicular to the tip tangent, or (compiled with
! -cpp -DDEAD_LOAD by run.sh: dead.exe) a dead tip force Lambda e1 fixed in space, rodkit's
! dead-load cantilever (benches/rod.rs, benches/rod_frontier.rs).
!   s = 0 : r = 0 (3), q = (1, 0, 0, 0) (4)                      -> 7 conditions
!   s = L : n_b = (Lambda, 0, 0) (force along the tip director d1), m_b = 0  -> 6 conditions
!           (dead: n_b = R(q)^T (Lambda, 0, 0), the spatial force Lambda e1 in the body frame)
! NBC = 13 = NDIM, NINT = 0: AUTO's count for one free parameter. All four components of q(0) are
! prescribed; this is an initial condition, not a constraint at both ends, so the conservation of
! |q| creates no redundancy (the linearised BVP is a shooting problem in the 6 unknowns n_b(0),
! m_b(0), nonsingular away from bifurcations). The rod bends in the (e1, e3) plane, towards +e1;
! the tip rotation is about e2, PAR(5) = 2 atan2(q2, q0) in degrees, positive.
! Stiffnesses: K_b1 = K_b2 = K_b = 1, K_t = 1/1.3 (nu = 0.3, round section), GA = 1e4,
! EA = 2.6 GA = 2.6e4 (EA/GA = 2(1+nu)), L = 1, so alpha = Lambda L^2/K_b = Lambda.
!---------------------------------------------------------------------------------------------------
SUBROUTINE FUNC(NDIM, U, ICP, PAR, IJAC, F, DFDU, DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  CALL ROD_RHS(U, PAR, F)
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM, U, PAR, T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
  PAR(21) = 1.0d0            ! K_b1
  PAR(22) = 1.0d0            ! K_b2
  PAR(23) = 1.0d0/1.3d0      ! K_t = K_b/(1+nu)
  PAR(24) = 1.0d4            ! GA
  PAR(25) = 2.6d4            ! EA = 2(1+nu) GA
  PAR(26) = 1.0d0            ! L
  CALL ROD_STPNT(U, PAR, T)
END SUBROUTINE STPNT

SUBROUTINE BCND(NDIM, PAR, ICP, NBC, U0, U1, FB, IJAC, DBC)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), NBC, IJAC
  DOUBLE PRECISION, INTENT(IN) :: PAR(*), U0(NDIM), U1(NDIM)
  DOUBLE PRECISION, INTENT(OUT) :: FB(NBC)
  DOUBLE PRECISION, INTENT(INOUT) :: DBC(NBC,*)
  DOUBLE PRECISION R(3,3)
  FB(1) = U0(1)
  FB(2) = U0(2)
  FB(3) = U0(3)
  FB(4) = U0(4) - 1.0d0
  FB(5) = U0(5)
  FB(6) = U0(6)
  FB(7) = U0(7)
#ifdef DEAD_LOAD
  CALL ROD_ROT(U1(4), R)
  FB(8) = U1(8) - PAR(1)*R(1,1)
  FB(9) = U1(9) - PAR(1)*R(1,2)
  FB(10) = U1(10) - PAR(1)*R(1,3)
#else
  FB(8) = U1(8) - PAR(1)
  FB(9) = U1(9)
  FB(10) = U1(10)
#endif
  FB(11) = U1(11)
  FB(12) = U1(12)
  FB(13) = U1(13)
END SUBROUTINE BCND

SUBROUTINE ICND
END SUBROUTINE ICND

SUBROUTINE FOPT
END SUBROUTINE FOPT

SUBROUTINE PVLS(NDIM, U, PAR)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: PAR(*)
  CALL ROD_PVLS(U, PAR)
END SUBROUTINE PVLS

INCLUDE 'rod_common.inc'
