!> Ghost cells of the ICE fields on non-periodic domain faces, from `&boundary` (one condition
!! per face, defaults: fluid 'wall', thermal 'adiabatic').
!!
!! Fluid conditions (ghost g, mirror cell c, prescribed face value q_b):
!!  - 'wall' (no slip): every velocity component odd (u_g = -u_c), face velocity 0.
!!  - 'free_slip': normal component odd, tangential even, face velocity 0.
!!  - 'pressure' (open face): pressure odd about the prescribed face pressure (p_g = 2 p_b - p_c),
!!    the pressure correction odd about 0 (Dirichlet in eq. 35: the face counts twice in the
!!    diagonal), velocities and scalars even, face velocity computed like an inner face and
!!    corrected by the pressure, face pressure p_b.
!!  - 'inflow': every velocity component odd about `&boundary velocity` (u_g = 2 u_b - u_c, so the
!!    face mean is u_b), scalars even (the inflowing fluid carries the density, volume fraction,
!!    specific volume and temperature of the inner cell next to the face; thermal 'fixed' sets the
!!    face temperature), pressure and pressure correction even. The face velocity of every fluid is
!!    the normal component of u_b and the pressure does not correct it (homogeneous Neumann on dp:
!!    the face is absent from the operator, its flux is part of the right-hand side).
!!  - `inflow_fluid` (faces 'pressure', 'inflow', 'outflow'): the volume that the fluids carry
!!    in through the face is filled with that fluid alone (`ice_advection`, open_face_inflow).
!!  - 'outflow' (zero gradient): every ghost even (velocities, scalars, pressure, pressure
!!    correction); the face velocity is computed like an inner face (with even ghosts: the inner
!!    cell's mass-weighted velocity plus dt g) and not corrected (homogeneous Neumann on dp).
!! Walls, inflow and outflow faces are "closed" to the pressure correction (`state%closed`,
!! used through `closed_face`); only 'pressure' faces are open. Thermal: 'adiabatic' (temperature
!! even: zero flux) or 'fixed' (ghost 2 T_wall - T, so the face temperature is T_wall). Other
!! scalars are mirrored. Called after the halo exchange; dimensions are filled in order x, y, z
!! over the full extent of the others so that edges and corners beyond a face are filled too.
module ice_bc
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use config_types, only: boundary_params_t
  use scene_params, only: ice_scene_params_t
  use grid_layout, only: grid_t
  implicit none
  private

  public :: ice_bc_t, ice_bc_init, ice_bc_fill, bc_scalar, bc_temperature, bc_pressure, bc_dp
  public :: bc_wall, bc_free_slip, bc_open, bc_inflow, bc_outflow

  integer, parameter :: bc_scalar = 0       !< field kind = even scalar (density, pressure, ...)
  integer, parameter :: bc_temperature = -1 !< field kind = temperature-like (fixed walls: odd about T_w)
  integer, parameter :: bc_pressure = -2    !< field kind = pressure (open faces: odd about p_b)
  integer, parameter :: bc_dp = -3          !< field kind = pressure correction (open faces: odd about 0)

  integer, parameter :: bc_wall = 1         !< fluid condition 'wall'
  integer, parameter :: bc_free_slip = 2    !< fluid condition 'free_slip'
  integer, parameter :: bc_open = 3         !< fluid condition 'pressure'
  integer, parameter :: bc_inflow = 4       !< fluid condition 'inflow'
  integer, parameter :: bc_outflow = 5      !< fluid condition 'outflow'

  !> Conditions of the six faces (x-, x+, y-, y+, z-, z+).
  type :: ice_bc_t
    integer :: fluid(6) = bc_wall           !< fluid condition (bc_wall .. bc_outflow)
    logical :: no_slip(6) = .true.          !< 'wall' (else 'free_slip' or open)
    logical :: open(6) = .false.            !< 'pressure': fluid may cross, p prescribed
    real(wp) :: p_face(6) = 101325.0_wp     !< pressure of an open face [Pa]
    real(wp) :: u_in(3, 6) = 0.0_wp         !< velocity of an inflow face [m/s]
    integer :: inflow_fluid(6) = 0          !< the fluid entering a face (0: the inner cell's mix)
    logical :: fixed_t(6) = .false.         !< thermal 'fixed' (else 'adiabatic')
    real(wp) :: t_wall(6) = 300.0_wp        !< wall temperature [K]
  end type ice_bc_t

contains

  !> Conditions from the scene's `&boundary` groups (resolved per face) and `&fluid` names.
  subroutine ice_bc_init(bc, par)
    type(ice_bc_t), intent(out) :: bc   !< face conditions
    type(ice_scene_params_t), intent(in) :: par  !< the ICE scene's groups
    type(boundary_params_t) :: b
    integer :: f, m
    do f = 1, 6
      b = par%faces(f)
      do m = 1, par%nfluids
        if (par%fluids(m)%name == b%inflow_fluid .and. len_trim(b%inflow_fluid) > 0) then
          bc%inflow_fluid(f) = m
        end if
      end do
      bc%no_slip(f) = .false.
      select case (trim(b%fluid))
      case ('wall')
        bc%fluid(f) = bc_wall
        bc%no_slip(f) = .true.
      case ('free_slip')
        bc%fluid(f) = bc_free_slip
      case ('pressure')
        bc%fluid(f) = bc_open
        bc%open(f) = .true.
        bc%p_face(f) = b%pressure
      case ('inflow')
        bc%fluid(f) = bc_inflow
        bc%u_in(:, f) = b%velocity
      case ('outflow')
        bc%fluid(f) = bc_outflow
      case default
        call fatal('ice scene: &boundary face = ''' // trim(b%face) // ''' fluid = ''' // &
          trim(b%fluid) // ''' is not implemented (wall, free_slip, pressure, inflow, outflow)')
      end select
      bc%fixed_t(f) = trim(b%thermal) == 'fixed'
      bc%t_wall(f) = b%temperature
    end do
  end subroutine ice_bc_init

  !> Fill the ghosts of `field` beyond non-periodic domain faces. `kind`: `bc_scalar`,
  !! `bc_temperature` (then `scale` multiplies T_wall: 1 for T, cv for cv T), `bc_pressure`,
  !! `bc_dp` or the velocity component 1..3 (mass-specific momentum too).
  subroutine ice_bc_fill(grid, bc, field, kind, scale)
    type(grid_t), intent(in) :: grid          !< block geometry
    type(ice_bc_t), intent(in) :: bc          !< face conditions
    real(wp), intent(inout) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    integer, intent(in) :: kind               !< field kind
    real(wp), intent(in), optional :: scale   !< factor of T_wall for bc_temperature
    integer :: d, g, lo, hi, side, f
    real(wp) :: s(2), w(2), sc

    sc = 1.0_wp
    if (present(scale)) sc = scale
    do d = 1, 3
      if (.not. grid%active(d) .or. grid%periodic(d)) cycle
      do side = 1, 2
        f = 2 * (d - 1) + side
        s(side) = 1.0_wp
        w(side) = 0.0_wp
        if (kind > 0) then
          ! velocity component `kind` across a face normal to d
          select case (bc%fluid(f))
          case (bc_wall)
            s(side) = -1.0_wp
          case (bc_free_slip)
            if (kind == d) s(side) = -1.0_wp
          case (bc_inflow)
            s(side) = -1.0_wp
            w(side) = 2.0_wp * bc%u_in(kind, f)
          case default
            ! pressure and outflow faces: even
          end select
        else if (kind == bc_pressure .and. bc%open(f)) then
          s(side) = -1.0_wp
          w(side) = 2.0_wp * bc%p_face(f)
        else if (kind == bc_dp .and. bc%open(f)) then
          s(side) = -1.0_wp
        else if (kind == bc_temperature .and. bc%fixed_t(f)) then
          s(side) = -1.0_wp
          w(side) = 2.0_wp * sc * bc%t_wall(f)
        end if
      end do
      lo = grid%lo(d)
      hi = grid%hi(d)
      do g = 1, grid%ng(d)
        select case (d)
        case (1)
          if (grid%at_lower(1)) field(lo - g, :, :) = w(1) + s(1) * field(lo + g - 1, :, :)
          if (grid%at_upper(1)) field(hi + g, :, :) = w(2) + s(2) * field(hi - g + 1, :, :)
        case (2)
          if (grid%at_lower(2)) field(:, lo - g, :) = w(1) + s(1) * field(:, lo + g - 1, :)
          if (grid%at_upper(2)) field(:, hi + g, :) = w(2) + s(2) * field(:, hi - g + 1, :)
        case default
          if (grid%at_lower(3)) field(:, :, lo - g) = w(1) + s(1) * field(:, :, lo + g - 1)
          if (grid%at_upper(3)) field(:, :, hi + g) = w(2) + s(2) * field(:, :, hi - g + 1)
        end select
      end do
    end do
  end subroutine ice_bc_fill
end module ice_bc
