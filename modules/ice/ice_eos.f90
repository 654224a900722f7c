!> Equations of state of the ICE fluids: ideal gas (paper eq. 10), linear water (eq. 11 in the
!! corrected form of errata E3) and a stiffened gas.
!!
!! Every function is elemental in the state and takes the material's parameters in an `eos_t`.
!! Temperatures in K, densities are intrinsic (micro) densities [kg/m^3], pressures in Pa.
!! * ideal gas:      p = (gamma - 1) rho cv T                                     (eq. 10)
!! * linear water:   p = p_ref + (K/rho_ref) (rho - rho_ref + alpha (T - T_ref))  (eq. 11, E3)
!! * stiffened gas:  p = (gamma - 1) rho cv T - p_inf
!! The squared sound speed is c^2 = dp/drho|_e + (dp/de|_rho) p / rho^2 with e = cv T (as Uintah's
!! ICE computes it); it reduces to gamma p / rho for the ideal gas and to (gamma p + p_inf) / rho
!! for the stiffened gas.
module ice_eos
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: eos_t, eos_ideal_gas, eos_linear_water, eos_stiffened_gas
  public :: eos_pressure, eos_density, eos_dp_drho, eos_sound_speed2, eos_kind_from_name

  integer, parameter :: eos_ideal_gas = 1      !< eq. 10
  integer, parameter :: eos_linear_water = 2   !< eq. 11 with errata E3
  integer, parameter :: eos_stiffened_gas = 3  !< stiffened gas
  !> the `&fluid eos` names of the kinds, in their order
  character(len=*), parameter :: eos_kind_names(3) = [character(len=13) :: 'ideal_gas', &
    'linear_water', 'stiffened_gas']

  !> Parameters of one material's equation of state.
  type :: eos_t
    integer :: kind = eos_ideal_gas                 !< eos_ideal_gas, eos_linear_water, eos_stiffened_gas
    real(wp) :: gamma = 1.4_wp                      !< ratio of specific heats
    real(wp) :: cv = 717.5_wp                       !< c_v [J/kg/K]
    real(wp) :: rho_ref = 999.8_wp                  !< reference density [kg/m^3]
    real(wp) :: p_ref = 101325.0_wp                 !< reference pressure [Pa]
    real(wp) :: t_ref = 283.15_wp                   !< reference temperature [K]
    real(wp) :: bulk_modulus = 2.0e9_wp             !< K [Pa]
    real(wp) :: alpha = 0.18_wp                     !< thermal expansion [kg/m^3/K]
    real(wp) :: p_inf = 0.0_wp                      !< stiffened-gas pressure [Pa]
  end type eos_t

contains

  !> EOS kind of a `&fluid eos` name (0 when unknown).
  pure integer function eos_kind_from_name(name) result(kind)
    character(len=*), intent(in) :: name  !< one of config_materials%eos_names
    kind = findloc(eos_kind_names, name, dim=1)
  end function eos_kind_from_name

  !> Pressure [Pa] at intrinsic density `rho` [kg/m^3] and temperature `t` [K].
  elemental function eos_pressure(e, rho, t) result(p)
    type(eos_t), intent(in) :: e  !< parameters
    real(wp), intent(in) :: rho   !< intrinsic density [kg/m^3]
    real(wp), intent(in) :: t     !< temperature [K]
    real(wp) :: p
    select case (e%kind)
    case (eos_linear_water)
      ! eq. 11, errata E3: K/rho_ref scaling and + alpha (T - T_ref)
      p = e%p_ref + e%bulk_modulus / e%rho_ref * (rho - e%rho_ref + e%alpha * (t - e%t_ref))
    case (eos_stiffened_gas)
      p = (e%gamma - 1.0_wp) * rho * e%cv * t - e%p_inf
    case default
      p = (e%gamma - 1.0_wp) * rho * e%cv * t   ! eq. 10 with R = (gamma - 1) cv
    end select
  end function eos_pressure

  !> Intrinsic density [kg/m^3] at pressure `p` [Pa] and temperature `t` [K] (inverse EOS).
  elemental function eos_density(e, p, t) result(rho)
    type(eos_t), intent(in) :: e  !< parameters
    real(wp), intent(in) :: p     !< pressure [Pa]
    real(wp), intent(in) :: t     !< temperature [K]
    real(wp) :: rho
    select case (e%kind)
    case (eos_linear_water)
      rho = e%rho_ref - e%alpha * (t - e%t_ref) + (p - e%p_ref) * e%rho_ref / e%bulk_modulus
    case (eos_stiffened_gas)
      rho = (p + e%p_inf) / ((e%gamma - 1.0_wp) * e%cv * t)
    case default
      rho = p / ((e%gamma - 1.0_wp) * e%cv * t)
    end select
  end function eos_density

  !> Isothermal derivative dp/drho [m^2/s^2] (used by the equilibration Newton iteration).
  elemental real(wp) function eos_dp_drho(e, rho, t) result(d)
    type(eos_t), intent(in) :: e  !< parameters
    real(wp), intent(in) :: rho   !< intrinsic density [kg/m^3]
    real(wp), intent(in) :: t     !< temperature [K]
    select case (e%kind)
    case (eos_linear_water)
      d = e%bulk_modulus / e%rho_ref + 0.0_wp * rho
    case default
      d = (e%gamma - 1.0_wp) * e%cv * t + 0.0_wp * rho
    end select
  end function eos_dp_drho

  !> Squared sound speed c^2 = dp/drho + dp/de p/rho^2 [m^2/s^2], e = cv T.
  elemental function eos_sound_speed2(e, rho, t) result(c2)
    type(eos_t), intent(in) :: e  !< parameters
    real(wp), intent(in) :: rho   !< intrinsic density [kg/m^3]
    real(wp), intent(in) :: t     !< temperature [K]
    real(wp) :: c2, p, dpde
    p = eos_pressure(e, rho, t)
    select case (e%kind)
    case (eos_linear_water)
      dpde = e%bulk_modulus * e%alpha / (e%rho_ref * e%cv)
    case default
      dpde = (e%gamma - 1.0_wp) * rho
    end select
    c2 = eos_dp_drho(e, rho, t) + dpde * p / rho**2
  end function eos_sound_speed2
end module ice_eos
