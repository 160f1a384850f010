!---------------------------------------------------------------------------------------------------
! AUTO-07p problem "euler": Euler buckling of the clamped-free Cosserat rod (physics.md §2.1,
! quaternion form, 13 ODEs) under an axial DEAD compressive tip load.
!   s = 0 : r = 0 (3), q = (1, 0, 0, 0) (4)
!   s = L : n(L) = (0, 0, -Lambda) in space, i.e. n_b(L) = R(q(L))^T (0, 0, -Lambda) (3), m_b = 0 (3)
! NBC = 13 = NDIM, NINT = 0 (see follower.f90 for why the 4 quaternion conditions at s = 0 are not
! redundant).
! Symmetry: the isotropic rod buckles at a DOUBLE branch point (any azimuth), where the determinant
! test of AUTO does not change sign and branch switching is ill-posed. The plane is fixed by making
! the rod stiffer about d1: K_b1 = 2 K_b, K_b2 = K_b. Planar solutions in the (e1, e3) plane have
! u1 = u3 = 0 (m1 = m3 = 0), so neither K_b1 nor K_t enters them: the critical load (bending about
! d2, stiffness K_b2 = K_b) and the whole post-buckled planar branch are EXACTLY those of the
! isotropic rod; the second (out-of-plane) branch point moves to about 2 P_cr.
! Stiffnesses: K_b = 1, K_t = 1/1.3, GA = 1e4, EA = 2.6e4, L = 1. Critical load (physics.md §2.6):
! P (1 + P (1/GA - 1/EA)) = pi^2 K_b / (4 L^2).
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
  PAR(21) = 2.0d0            ! K_b1 = 2 K_b: fixes the buckling plane (e1, e3)
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
  DOUBLE PRECISION q0, q1, q2, q3
  FB(1) = U0(1)
  FB(2) = U0(2)
  FB(3) = U0(3)
  FB(4) = U0(4) - 1.0d0
  FB(5) = U0(5)
  FB(6) = U0(6)
  FB(7) = U0(7)
  ! n_b(L) + Lambda R(q(L))^T e3 = 0 (R^T e3 = third row of R)
  q0 = U1(4); q1 = U1(5); q2 = U1(6); q3 = U1(7)
  FB(8) = U1(8) + PAR(1)*2.0d0*(q1*q3 - q0*q2)
  FB(9) = U1(9) + PAR(1)*2.0d0*(q2*q3 + q0*q1)
  FB(10) = U1(10) + PAR(1)*(q0*q0 - q1*q1 - q2*q2 + q3*q3)
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
