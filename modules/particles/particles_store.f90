!> Particle store of one solid material: structure of arrays, owned by the rank whose block
!! contains the particle.
!!
!! Capacity grows only in `particles_reserve` (amortised doubling), which the scene calls at
!! seeding and in the migration step, never inside the kernels. Tensors are stored as
!! * `f(9, np)`: deformation gradient, column-major 3x3 (`f(1:3)` is the first column);
!! * `stress(6, np)`, `stress_unrot(6, np)`: symmetric tensors in the order xx, yy, zz, xy, yz, xz,
!!   tension positive [Pa]. `stress` is the Cauchy (effective) stress in the current frame, used by
!!   P2G; `stress_unrot` = R^T stress R is the same stress in the polar-decomposition frame of
!!   eqs. 12-15, the state of the rate-form constitutive models.
!!
!! The model-specific state exists only in a store whose solid's model uses it
!! (`mpm_constitutive%model_state`, set by `particles_select_state` before the first
!! allocation): `hardening` (Cam-Clay) when `has_hardening`, `cyclic` (critical-state sand with
!! densification) when `has_cyclic`, `gap` (critical-state sand with `&solid tension_gap`) when
!! `has_gap`, `affine` (the APIC velocity transfer, `&mpm velocity_transfer = 'apic'`) when
!! `has_affine`; otherwise those arrays stay unallocated, and
!! are neither migrated nor checkpointed.
module particles_store
  use mpmice_kinds, only: wp, i8
  implicit none
  private

  public :: particles_t, particles_reserve, particles_resize, particles_compact
  public :: particles_free, identity_f, n_cyclic_state, n_affine, particles_select_state

  !> Entries of the per-particle cyclic state (`mpm_critical_state_sand`'s css_n_cyclic).
  integer, parameter :: n_cyclic_state = 6

  !> Entries of the per-particle affine velocity matrix C_p (3x3, column-major as `f`).
  integer, parameter :: n_affine = 9

  !> 3x3 identity as stored in `f(9)`.
  real(wp), parameter :: identity_f(9) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 1.0_wp]

  !> Particles of one solid material on this rank.
  type :: particles_t
    integer :: np = 0                          !< particles in use
    integer :: capacity = 0                    !< allocated length
    real(wp) :: half_width(3) = 0.0_wp         !< GIMP particle half-width l_p per dimension [m]
    logical :: has_hardening = .false.         !< `hardening` allocated (Cam-Clay)
    logical :: has_cyclic = .false.            !< `cyclic` allocated (sand with densification)
    logical :: has_gap = .false.               !< `gap` allocated (sand with `tension_gap`)
    logical :: has_affine = .false.            !< `affine` allocated (APIC velocity transfer)
    real(wp), allocatable :: x(:, :)           !< (3, np) position [m]
    real(wp), allocatable :: v(:, :)           !< (3, np) velocity [m/s]
    real(wp), allocatable :: mass(:)           !< mass [kg]
    real(wp), allocatable :: volume(:)         !< current volume [m^3]
    real(wp), allocatable :: volume0(:)        !< initial volume [m^3]
    real(wp), allocatable :: f(:, :)           !< (9, np) deformation gradient [-]
    real(wp), allocatable :: stress(:, :)      !< (6, np) Cauchy effective stress [Pa]
    real(wp), allocatable :: stress_unrot(:, :) !< (6, np) stress in the rotated frame [Pa]
    real(wp), allocatable :: plastic_strain(:) !< accumulated equivalent plastic strain [-]
    !> hardening variable of the model: Modified Cam-Clay preconsolidation pressure p_c [Pa]
    !! (0: not yet set) or the critical-state sand's compaction pressure p_c [Pa]; allocated
    !! only when `has_hardening`
    real(wp), allocatable :: hardening(:)
    !> (n_cyclic_state, np) cyclic densification state of the critical-state sand
    !! (`css_densify`: eps_vd, gamma_xy, its last reversal and extreme, reversals, time since
    !! the last reversal); 0 at seeding; allocated only when `has_cyclic`
    real(wp), allocatable :: cyclic(:, :)
    !> volumetric gap of the critical-state sand (`css_tension_gap`): the expansion a particle
    !! at zero effective stress has opened, closed stress-free before it carries load again
    !! [-]; 0 at seeding; allocated only when `has_gap`
    real(wp), allocatable :: gap(:)
    !> (n_affine, np) affine velocity C_p [1/s] of the APIC transfer (column-major 3x3: the
    !! particle's velocity at x is v_p + C_p (x - x_p)); 0 at seeding; allocated only when
    !! `has_affine`
    real(wp), allocatable :: affine(:, :)
    real(wp), allocatable :: temperature(:)    !< temperature [K]
    real(wp), allocatable :: pore_pressure(:)  !< pore pressure (0 without a fluid) [Pa]
    integer(i8), allocatable :: id(:)          !< global particle id (unique, stable)
  end type particles_t

contains

  !> Choose the model-specific state of an empty store (before its first allocation).
  subroutine particles_select_state(p, hardening, cyclic, gap, affine)
    type(particles_t), intent(inout) :: p  !< store, not yet allocated
    logical, intent(in) :: hardening       !< keep the Cam-Clay p_c
    logical, intent(in) :: cyclic          !< keep the sand's cyclic state
    logical, intent(in) :: gap             !< keep the sand's volumetric gap
    logical, intent(in) :: affine          !< keep the APIC affine velocity
    p%has_hardening = hardening
    p%has_cyclic = cyclic
    p%has_gap = gap
    p%has_affine = affine
  end subroutine particles_select_state

  !> Make room for at least `n` particles, keeping the first `np`. Grows to max(n, 2 capacity)
  !! so repeated calls cost amortised O(1) per particle.
  subroutine particles_reserve(p, n)
    type(particles_t), intent(inout) :: p  !< store
    integer, intent(in) :: n               !< particles needed
    if (n <= p%capacity .and. allocated(p%x)) return
    call particles_resize(p, max(n, 2 * p%capacity, 16))
  end subroutine particles_reserve

  !> Set the capacity to exactly `cap` (>= np), keeping the particles in use.
  subroutine particles_resize(p, cap)
    type(particles_t), intent(inout) :: p  !< store
    integer, intent(in) :: cap             !< new capacity
    type(particles_t) :: q
    integer :: n
    n = min(p%np, cap)
    allocate(q%x(3, cap), q%v(3, cap), q%mass(cap), q%volume(cap), q%volume0(cap), q%f(9, cap), &
      q%stress(6, cap), q%stress_unrot(6, cap), q%plastic_strain(cap), q%temperature(cap), &
      q%pore_pressure(cap), q%id(cap))
    if (p%has_hardening) allocate(q%hardening(cap))
    if (p%has_cyclic) allocate(q%cyclic(n_cyclic_state, cap))
    if (p%has_gap) allocate(q%gap(cap))
    if (p%has_affine) allocate(q%affine(n_affine, cap))
    if (n > 0) then
      q%x(:, 1:n) = p%x(:, 1:n)
      q%v(:, 1:n) = p%v(:, 1:n)
      q%mass(1:n) = p%mass(1:n)
      q%volume(1:n) = p%volume(1:n)
      q%volume0(1:n) = p%volume0(1:n)
      q%f(:, 1:n) = p%f(:, 1:n)
      q%stress(:, 1:n) = p%stress(:, 1:n)
      q%stress_unrot(:, 1:n) = p%stress_unrot(:, 1:n)
      q%plastic_strain(1:n) = p%plastic_strain(1:n)
      if (p%has_hardening) q%hardening(1:n) = p%hardening(1:n)
      if (p%has_cyclic) q%cyclic(:, 1:n) = p%cyclic(:, 1:n)
      if (p%has_gap) q%gap(1:n) = p%gap(1:n)
      if (p%has_affine) q%affine(:, 1:n) = p%affine(:, 1:n)
      q%temperature(1:n) = p%temperature(1:n)
      q%pore_pressure(1:n) = p%pore_pressure(1:n)
      q%id(1:n) = p%id(1:n)
    end if
    call move_alloc(q%x, p%x)
    call move_alloc(q%v, p%v)
    call move_alloc(q%mass, p%mass)
    call move_alloc(q%volume, p%volume)
    call move_alloc(q%volume0, p%volume0)
    call move_alloc(q%f, p%f)
    call move_alloc(q%stress, p%stress)
    call move_alloc(q%stress_unrot, p%stress_unrot)
    call move_alloc(q%plastic_strain, p%plastic_strain)
    if (p%has_hardening) call move_alloc(q%hardening, p%hardening)
    if (p%has_cyclic) call move_alloc(q%cyclic, p%cyclic)
    if (p%has_gap) call move_alloc(q%gap, p%gap)
    if (p%has_affine) call move_alloc(q%affine, p%affine)
    call move_alloc(q%temperature, p%temperature)
    call move_alloc(q%pore_pressure, p%pore_pressure)
    call move_alloc(q%id, p%id)
    p%np = n
    p%capacity = cap
  end subroutine particles_resize

  !> Remove the particles with `keep(i) = .false.`, preserving the order of the others.
  subroutine particles_compact(p, keep)
    type(particles_t), intent(inout) :: p  !< store
    logical, intent(in) :: keep(:)         !< (np) particles to keep
    integer :: i, j
    j = 0
    do i = 1, p%np
      if (.not. keep(i)) cycle
      j = j + 1
      if (j == i) cycle
      p%x(:, j) = p%x(:, i)
      p%v(:, j) = p%v(:, i)
      p%mass(j) = p%mass(i)
      p%volume(j) = p%volume(i)
      p%volume0(j) = p%volume0(i)
      p%f(:, j) = p%f(:, i)
      p%stress(:, j) = p%stress(:, i)
      p%stress_unrot(:, j) = p%stress_unrot(:, i)
      p%plastic_strain(j) = p%plastic_strain(i)
      if (p%has_hardening) p%hardening(j) = p%hardening(i)
      if (p%has_cyclic) p%cyclic(:, j) = p%cyclic(:, i)
      if (p%has_gap) p%gap(j) = p%gap(i)
      if (p%has_affine) p%affine(:, j) = p%affine(:, i)
      p%temperature(j) = p%temperature(i)
      p%pore_pressure(j) = p%pore_pressure(i)
      p%id(j) = p%id(i)
    end do
    p%np = j
  end subroutine particles_compact

  !> Release the arrays.
  subroutine particles_free(p)
    type(particles_t), intent(inout) :: p  !< store
    if (allocated(p%x)) deallocate(p%x, p%v, p%mass, p%volume, p%volume0, p%f, p%stress, &
      p%stress_unrot, p%plastic_strain, p%temperature, p%pore_pressure, p%id)
    if (allocated(p%hardening)) deallocate(p%hardening)
    if (allocated(p%cyclic)) deallocate(p%cyclic)
    if (allocated(p%gap)) deallocate(p%gap)
    if (allocated(p%affine)) deallocate(p%affine)
    p%np = 0
    p%capacity = 0
  end subroutine particles_free
end module particles_store
