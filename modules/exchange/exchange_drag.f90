!> Drag laws between a fluid and the porous solid skeleton (paper eqs. 18-21, errata E7, E8).
!!
!! The exchange works with a *reduced* coefficient c [kg/m^3/s]: the drag force per unit volume on
!! fluid m is f_d = phi_m phi_s c (u_s - u_m), so that beta_mn = dt v_m phi_n c in Uintah's
!! convention (`ice_exchange`). For one fluid filling the pores (phi_m = n = 1 - phi_s), eq. 18
!! f_d = 18 phi_s (1 - phi_s) mu F / d^2 (u_s - u_f) gives c = 18 mu F / d^2; with several fluids
!! each gets the share of eq. 18 of its volume fraction, with its own viscosity.
!!
!! Laws (`&solid drag_law`):
!! * 'kozeny_carman': F = 10 phi_s / (1 - phi_s)^2, the low-Reynolds limit that makes eq. 77
!!   exact (errata E7: drag per volume 180 phi_s^2 mu / (d^2 (1 - phi_s)));
!! * 'beetstra': F(phi_s, Re) of eqs. 20-21 as printed, Re = n rho_f d |u_s - u_f| / mu (eq. 19);
!! * 'constant': f_d = K (u_s - u_f) with K = `&solid drag_coefficient` for the whole pore fluid,
!!   shared among the fluids by volume fraction: c = K / (n phi_s);
!! * 'impermeable': c = 1e15 kg/m^3/s (the fluid moves with a structure: Uintah's value);
!! * 'forchheimer': the Ergun / van Gent law for coarse grains,
!!   -dp/dx = a mu phi_s^2 / (n^3 d^2) q + b rho_f phi_s / (n^3 d) |q| q, q = n (u_f - u_s) the
!!   Darcy flux, a and b from `&solid forchheimer_a`, `forchheimer_b` (Ergun: 150, 1.75). The
!!   drag on the pore fluid balances n (-dp/dx) in a steady rigid column, so phi_s c w = -dp/dx
!!   with w = |u_s - u_f| and c = a mu phi_s / (n^2 d^2) + b rho_f w / (n d). a = 180, b = 0 is
!!   'kozeny_carman' exactly. w is the slip of the velocities at the start of the step (lagged,
!!   as for 'beetstra'): the exchange stays linear and implicit, and a steady state is exact.
module exchange_drag
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: drag_law_from_name, drag_reduced_coefficient, beetstra_factor, kozeny_carman_factor, &
    drag_kozeny_carman, drag_beetstra, drag_constant, drag_impermeable, drag_forchheimer, &
    ergun_a, ergun_b, forchheimer_bed_t, forchheimer_gradient, forchheimer_flux

  integer, parameter :: drag_kozeny_carman = 1  !< F = 10 phi / (1 - phi)^2
  integer, parameter :: drag_beetstra = 2       !< F(phi, Re) of eqs. 20-21
  integer, parameter :: drag_constant = 3       !< constant K per volume
  integer, parameter :: drag_impermeable = 4    !< structure: very stiff coupling
  integer, parameter :: drag_forchheimer = 5    !< Ergun / van Gent: linear + quadratic in q
  !> the `&solid drag_law` names of the laws, in their order
  character(len=*), parameter :: drag_law_names(5) = [character(len=13) :: 'kozeny_carman', &
    'beetstra', 'constant', 'impermeable', 'forchheimer']

  real(wp), parameter :: ergun_a = 150.0_wp     !< Ergun's linear coefficient a [-]
  real(wp), parameter :: ergun_b = 1.75_wp      !< Ergun's quadratic coefficient b [-]

  real(wp), parameter :: impermeable_coefficient = 1.0e15_wp  !< c of an impermeable solid

  !> A rigid bed of grains and the fluid in its pores, for the Forchheimer law
  !! (`forchheimer_gradient`, `forchheimer_flux`).
  type :: forchheimer_bed_t
    real(wp) :: porosity = 0.5_wp       !< n [-], 0 < n < 1
    real(wp) :: grain_size = 1.0e-3_wp  !< grain diameter d [m]
    real(wp) :: viscosity = 1.0e-3_wp   !< mu [Pa s]
    real(wp) :: rho_fluid = 1000.0_wp   !< intrinsic fluid density [kg/m^3]
    real(wp) :: a = ergun_a             !< linear coefficient [-]
    real(wp) :: b = ergun_b             !< quadratic coefficient [-]
  end type forchheimer_bed_t

contains

  !> Law id of a `&solid drag_law` value (validated by the configuration; unknown names:
  !! kozeny_carman).
  pure integer function drag_law_from_name(name) result(law)
    character(len=*), intent(in) :: name  !< namelist value
    law = max(findloc(drag_law_names, name, dim=1), drag_kozeny_carman)
  end function drag_law_from_name

  !> Kozeny-Carman factor F = 10 phi_s / (1 - phi_s)^2 (paper below eq. 21, eq. 77).
  elemental real(wp) function kozeny_carman_factor(phi_s) result(f)
    real(wp), intent(in) :: phi_s  !< solid volume fraction [-], < 1
    f = 10.0_wp * phi_s / (1.0_wp - phi_s)**2
  end function kozeny_carman_factor

  !> F(phi_s, Re) of eqs. 20-21 as printed (Beetstra et al. fit, valid 0.1 < phi_s < 0.6,
  !! Re < 1000; errata E7). Re = 0 gives the low-Reynolds value of eq. 21.
  elemental real(wp) function beetstra_factor(phi_s, re) result(f)
    real(wp), intent(in) :: phi_s  !< solid volume fraction [-], < 1
    real(wp), intent(in) :: re     !< particle Reynolds number of eq. 19 [-], >= 0
    real(wp) :: n
    n = 1.0_wp - phi_s
    f = 10.0_wp * phi_s / n**2 + n**2 * (1.0_wp + 1.5_wp * sqrt(phi_s))            ! eq. 21
    if (re > 0.0_wp) f = f + 0.413_wp * re / (24.0_wp * n**2) * &                 ! eq. 20
      (1.0_wp / n + 3.0_wp * phi_s * n + 8.4_wp * re**(-0.343_wp)) / &
      (1.0_wp + 10.0_wp**(3.0_wp * phi_s) * re**(-(1.0_wp + 4.0_wp * phi_s) / 2.0_wp))
  end function beetstra_factor

  !> Pressure gradient -dp/dx [Pa/m] that drives the Darcy flux q [m/s] through a rigid bed of
  !! the Forchheimer law in the Ergun / van Gent form (sign of q):
  !! a mu (1-n)^2 / (n^3 d^2) q + b rho (1-n) / (n^3 d) |q| q = (A + B |q|) q.
  elemental real(wp) function forchheimer_gradient(q, bed) result(g)
    real(wp), intent(in) :: q                       !< Darcy flux n (u_f - u_s) [m/s]
    type(forchheimer_bed_t), intent(in) :: bed      !< the bed and its fluid
    real(wp) :: lin, quad
    call forchheimer_terms(bed, lin, quad)
    g = (lin + quad * abs(q)) * q
  end function forchheimer_gradient

  !> Darcy flux q [m/s] of `forchheimer_gradient` for a given -dp/dx [Pa/m]: the root of
  !! B |q| q + A q = G with the sign of G, q = 2 G / (A + sqrt(A^2 + 4 B |G|)) (no
  !! cancellation at small B |G|; A > 0 or B > 0).
  elemental real(wp) function forchheimer_flux(gradient, bed) result(q)
    real(wp), intent(in) :: gradient                !< -dp/dx [Pa/m]
    type(forchheimer_bed_t), intent(in) :: bed      !< the bed and its fluid
    real(wp) :: lin, quad
    call forchheimer_terms(bed, lin, quad)
    q = 2.0_wp * gradient / (lin + sqrt(lin**2 + 4.0_wp * quad * abs(gradient)))
  end function forchheimer_flux

  !> The Forchheimer law's linear A = a mu (1-n)^2 / (n^3 d^2) [Pa s/m^2] and quadratic
  !! B = b rho (1-n) / (n^3 d) [kg/m^4] coefficients of `bed`.
  elemental subroutine forchheimer_terms(bed, lin, quad)
    type(forchheimer_bed_t), intent(in) :: bed      !< the bed and its fluid
    real(wp), intent(out) :: lin                    !< A [Pa s/m^2]
    real(wp), intent(out) :: quad                   !< B [kg/m^4]
    real(wp) :: phi_s
    phi_s = 1.0_wp - bed%porosity
    lin = bed%a * bed%viscosity * phi_s**2 / (bed%porosity**3 * bed%grain_size**2)
    quad = bed%b * bed%rho_fluid * phi_s / (bed%porosity**3 * bed%grain_size)
  end subroutine forchheimer_terms

  !> Reduced drag coefficient c [kg/m^3/s] between a fluid (viscosity mu, intrinsic density
  !! rho_f) and the solid (fraction phi_s, grain size d) at slip speed |u_s - u_f|.
  pure real(wp) function drag_reduced_coefficient(law, phi_s, grain_size, viscosity, &
      rho_fluid, slip, coefficient, forchheimer_a, forchheimer_b) result(c)
    integer, intent(in) :: law             !< drag_kozeny_carman, ...
    real(wp), intent(in) :: phi_s          !< solid volume fraction [-], 0 < phi_s < 1
    real(wp), intent(in) :: grain_size     !< grain diameter d [m]
    real(wp), intent(in) :: viscosity      !< fluid dynamic viscosity mu [Pa s]
    real(wp), intent(in) :: rho_fluid      !< intrinsic fluid density [kg/m^3]
    real(wp), intent(in) :: slip           !< |u_s - u_f| [m/s]
    real(wp), intent(in) :: coefficient    !< K of the constant law [kg/m^3/s]
    real(wp), intent(in), optional :: forchheimer_a  !< a of 'forchheimer' [-] (ergun_a)
    real(wp), intent(in), optional :: forchheimer_b  !< b of 'forchheimer' [-] (ergun_b)
    real(wp) :: re, n, a, b
    c = 0.0_wp
    if (phi_s <= 0.0_wp) return
    n = 1.0_wp - phi_s
    select case (law)
    case (drag_kozeny_carman)
      c = 18.0_wp * viscosity * kozeny_carman_factor(phi_s) / grain_size**2
    case (drag_beetstra)
      re = 0.0_wp
      if (viscosity > 0.0_wp) re = n * rho_fluid * grain_size * slip / viscosity    ! eq. 19
      c = 18.0_wp * viscosity * beetstra_factor(phi_s, re) / grain_size**2
    case (drag_constant)
      c = coefficient / (n * phi_s)
    case (drag_impermeable)
      c = impermeable_coefficient
    case (drag_forchheimer)
      a = ergun_a
      b = ergun_b
      if (present(forchheimer_a)) a = forchheimer_a
      if (present(forchheimer_b)) b = forchheimer_b
      c = a * viscosity * phi_s / (n**2 * grain_size**2) + b * rho_fluid * slip / &
        (n * grain_size)
    case default
      c = 0.0_wp    ! not reached: the configuration accepts only the laws above
    end select
  end function drag_reduced_coefficient
end module exchange_drag
