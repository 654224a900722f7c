!> HDF5 datasets of the MPM particles (design §7): dumps `/particles/<solid>/{x, y, z,
!! velocity_x.., stress_xx.., pore_pressure, temperature, volume, mass, plastic_strain,
!! hardening, id}` and
!! `/cell/<solid>/{volume_fraction, velocity_x, velocity_y, velocity_z, temperature}` (particle
!! volume per cell volume; mass-weighted particle averages, 0 in empty cells), and checkpoints
!! `/checkpoint/particles/<solid>/...` with the full state (bitwise restart). The dumps always
!! hold `hardening` (0 unless the solid is Cam-Clay or the sand with compaction); a checkpoint
!! holds `hardening`, `cyclic`, `cyclic_half_time`, `gap` and `affine` only for a solid whose
!! model carries them (`particles_store`).
module mpm_output
  use mpmice_kinds, only: wp, i8, name_len
  use io_hdf5, only: h5_file_t, h5_write_particles, h5_read_particles, h5_write_cell_field, &
    h5_exists
  use grid_layout, only: grid_t, clamped_cell
  use io_xdmf, only: xdmf_particles_t
  use particles_store, only: particles_t, particles_resize, n_cyclic_state
  use mpmice_errors, only: fatal
  implicit none
  private

  public :: write_particle_dump, write_particle_checkpoint, read_particle_checkpoint
  public :: particle_xdmf_set, write_cell_dump, cell_dump_paths

  character(len=2), parameter :: sym_names(6) = ['xx', 'yy', 'zz', 'xy', 'yz', 'xz']  !< stress
  character(len=1), parameter :: axis(3) = ['x', 'y', 'z']                          !< components

  !> Write a checkpoint's particle dataset from this rank's particle arrays, or read it into them.
  interface transfer
    module procedure transfer_rows, transfer_column
  end interface transfer

contains

  !> Dump datasets of one solid under `particles/<name>/` (collective).
  subroutine write_particle_dump(file, name, p)
    type(h5_file_t), intent(in) :: file    !< open dump
    character(len=*), intent(in) :: name   !< solid name
    type(particles_t), intent(in) :: p     !< particles
    character(len=:), allocatable :: g
    real(wp), allocatable :: tmp(:)
    integer :: d, n
    n = p%np
    g = 'particles/' // trim(name) // '/'
    allocate(tmp(n))
    do d = 1, 3
      tmp(:) = p%x(d, 1:n)
      call h5_write_particles(file, g // axis(d), tmp)
    end do
    do d = 1, 3
      tmp(:) = p%v(d, 1:n)
      call h5_write_particles(file, g // 'velocity_' // axis(d), tmp)
    end do
    do d = 1, 6
      tmp(:) = p%stress(d, 1:n)
      call h5_write_particles(file, g // 'stress_' // sym_names(d), tmp)
    end do
    call h5_write_particles(file, g // 'pore_pressure', p%pore_pressure(1:n))
    call h5_write_particles(file, g // 'temperature', p%temperature(1:n))
    call h5_write_particles(file, g // 'volume', p%volume(1:n))
    call h5_write_particles(file, g // 'mass', p%mass(1:n))
    call h5_write_particles(file, g // 'plastic_strain', p%plastic_strain(1:n))
    if (p%has_hardening) then
      call h5_write_particles(file, g // 'hardening', p%hardening(1:n))
    else
      tmp(:) = 0.0_wp  ! the dump layout is the same for every model
      call h5_write_particles(file, g // 'hardening', tmp)
    end if
    call h5_write_particles(file, g // 'id', p%id(1:n))
  end subroutine write_particle_dump

  !> The XDMF description of `write_particle_dump`'s datasets for `count` particles.
  function particle_xdmf_set(name, count) result(set)
    character(len=*), intent(in) :: name   !< solid name
    integer(i8), intent(in) :: count       !< particles of all ranks
    type(xdmf_particles_t) :: set
    integer :: d
    set%group = 'particles/' // trim(name)
    set%count = count
    allocate(set%fields(18))
    do d = 1, 3
      set%fields(d) = 'velocity_' // axis(d)
    end do
    do d = 1, 6
      set%fields(3 + d) = 'stress_' // sym_names(d)
    end do
    set%fields(10:18) = [character(len=name_len) :: 'pore_pressure', 'temperature', 'volume', &
      'mass', 'plastic_strain', 'hardening', 'x', 'y', 'z']
    set%int_fields = [character(len=name_len) :: 'id']
  end function particle_xdmf_set

  !> Full state of one solid under `checkpoint/particles/<name>/` (collective).
  subroutine write_particle_checkpoint(file, name, p)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: name     !< solid name
    type(particles_t), intent(inout) :: p    !< particles (unchanged)
    character(len=:), allocatable :: g
    g = 'checkpoint/particles/' // trim(name) // '/'
    call checkpoint_state(file, g, p, p%np, .true.)
    call h5_write_particles(file, g // 'id', p%id(1:p%np))
  end subroutine write_particle_checkpoint

  !> Replace the particles of one solid by this rank's chunk of a checkpoint (collective; the
  !! caller migrates them when the rank count changed).
  subroutine read_particle_checkpoint(file, name, p)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: name     !< solid name
    type(particles_t), intent(inout) :: p    !< particles
    character(len=:), allocatable :: g
    integer(i8), allocatable :: ids(:)
    integer :: n
    g = 'checkpoint/particles/' // trim(name) // '/'
    call h5_read_particles(file, g // 'id', ids)
    n = size(ids)
    p%np = 0
    call particles_resize(p, max(n, 16))
    p%np = n
    p%id(1:n) = ids
    call checkpoint_state(file, g, p, n, .false.)
  end subroutine read_particle_checkpoint

  !> Write (`write`) or read the particle arrays of a checkpoint but the ids, particles 1..n,
  !! under the group `g`: the one list of what a bitwise restart needs. The model-specific
  !! state is written and read only when the store carries it; a checkpoint that holds it for
  !! a store without it restarts (the datasets are skipped). A store that needs it from a
  !! checkpoint without it stops here (`driver_restart` refuses such a restart before).
  subroutine checkpoint_state(file, g, p, n, write)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: g        !< group path, ending in '/'
    type(particles_t), intent(inout) :: p    !< particles
    integer, intent(in) :: n                 !< particles on this rank
    logical, intent(in) :: write             !< write, else read
    integer, parameter :: cyclic_main = n_cyclic_state - 1  !< rows of `cyclic`
    call transfer(file, g // 'x', p%x(:, 1:n), write)
    call transfer(file, g // 'v', p%v(:, 1:n), write)
    call transfer(file, g // 'f', p%f(:, 1:n), write)
    call transfer(file, g // 'stress', p%stress(:, 1:n), write)
    call transfer(file, g // 'stress_unrot', p%stress_unrot(:, 1:n), write)
    call transfer(file, g // 'mass', p%mass(1:n), write)
    call transfer(file, g // 'volume', p%volume(1:n), write)
    call transfer(file, g // 'volume0', p%volume0(1:n), write)
    call transfer(file, g // 'plastic_strain', p%plastic_strain(1:n), write)
    if (p%has_hardening) then
      call require(file, g // 'hardening', write)
      call transfer(file, g // 'hardening', p%hardening(1:n), write)
    end if
    if (p%has_cyclic) then
      ! the sand's cyclic densification state; the time since the last reversal is its own
      ! dataset (`cyclic` keeps its five rows)
      call require(file, g // 'cyclic', write)
      call require(file, g // 'cyclic_half_time', write)
      call transfer(file, g // 'cyclic', p%cyclic(1:cyclic_main, 1:n), write)
      call transfer(file, g // 'cyclic_half_time', p%cyclic(n_cyclic_state, 1:n), write)
    end if
    if (p%has_gap) then
      ! the sand's volumetric gap (`&solid tension_gap`)
      call require(file, g // 'gap', write)
      call transfer(file, g // 'gap', p%gap(1:n), write)
    end if
    if (p%has_affine) then
      ! the APIC affine velocity C_p (`&mpm velocity_transfer = 'apic'`)
      call require(file, g // 'affine', write)
      call transfer(file, g // 'affine', p%affine(:, 1:n), write)
    end if
    call transfer(file, g // 'temperature', p%temperature(1:n), write)
    call transfer(file, g // 'pore_pressure', p%pore_pressure(1:n), write)
  end subroutine checkpoint_state

  !> Stop when reading a checkpoint that lacks the dataset `path` (collective).
  subroutine require(file, path, write)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: path     !< dataset path
    logical, intent(in) :: write             !< write (nothing to check), else read
    if (write) return
    if (.not. h5_exists(file, path)) call fatal('checkpoint lacks ' // path // &
      ', which the solid''s model needs')
  end subroutine require

  !> Write this rank's rows of the 2-D particle dataset `path`, or read them into `values`
  !! (same extent).
  subroutine transfer_rows(file, path, values, write)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: path     !< dataset path
    real(wp), intent(inout) :: values(:, :)  !< this rank's particles' values (ncomp, n)
    logical, intent(in) :: write             !< write, else read
    real(wp), allocatable :: stored(:, :)
    if (write) then
      call h5_write_particles(file, path, values)
    else
      call h5_read_particles(file, path, stored)
      values = stored
    end if
  end subroutine transfer_rows

  !> Write this rank's part of the 1-D particle dataset `path`, or read it into `values`
  !! (same length).
  subroutine transfer_column(file, path, values, write)
    type(h5_file_t), intent(in) :: file      !< open checkpoint
    character(len=*), intent(in) :: path     !< dataset path
    real(wp), intent(inout) :: values(:)     !< this rank's particles' values (n)
    logical, intent(in) :: write             !< write, else read
    real(wp), allocatable :: stored(:)
    if (write) then
      call h5_write_particles(file, path, values)
    else
      call h5_read_particles(file, path, stored)
      values = stored
    end if
  end subroutine transfer_column

  !> Cell dataset paths written by `write_cell_dump` for solid `name`.
  function cell_dump_paths(name) result(paths)
    character(len=*), intent(in) :: name   !< solid name
    character(len=name_len) :: paths(5)
    paths(1) = 'cell/' // trim(name) // '/volume_fraction'
    paths(2) = 'cell/' // trim(name) // '/velocity_x'
    paths(3) = 'cell/' // trim(name) // '/velocity_y'
    paths(4) = 'cell/' // trim(name) // '/velocity_z'
    paths(5) = 'cell/' // trim(name) // '/temperature'
  end function cell_dump_paths

  !> Cell averages of one solid's particles (each particle counts in the owned cell containing
  !! it) under `cell/<name>/` (collective).
  subroutine write_cell_dump(file, name, p, grid)
    type(h5_file_t), intent(in) :: file    !< open dump
    character(len=*), intent(in) :: name   !< solid name
    type(particles_t), intent(in) :: p     !< particles
    type(grid_t), intent(in) :: grid       !< block geometry
    real(wp), allocatable :: acc(:, :, :, :), field(:, :, :)
    character(len=name_len) :: paths(5)
    integer :: ip, d, c(3)
    allocate(acc(6, grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), grid%lbc(3):grid%ubc(3)), &
      source=0.0_wp)
    allocate(field(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), grid%lbc(3):grid%ubc(3)), &
      source=0.0_wp)
    do ip = 1, p%np
      c = clamped_cell(grid, p%x(:, ip), grid%lo, grid%hi)
      acc(1, c(1), c(2), c(3)) = acc(1, c(1), c(2), c(3)) + p%volume(ip)
      acc(2, c(1), c(2), c(3)) = acc(2, c(1), c(2), c(3)) + p%mass(ip)
      acc(3:5, c(1), c(2), c(3)) = acc(3:5, c(1), c(2), c(3)) + p%mass(ip) * p%v(:, ip)
      acc(6, c(1), c(2), c(3)) = acc(6, c(1), c(2), c(3)) + p%mass(ip) * p%temperature(ip)
    end do
    paths = cell_dump_paths(name)
    field(:, :, :) = acc(1, :, :, :) / grid%cell_volume
    call h5_write_cell_field(file, trim(paths(1)), grid, field)
    do d = 1, 4
      field(:, :, :) = merge(acc(2 + d, :, :, :) / max(acc(2, :, :, :), tiny(1.0_wp)), 0.0_wp, &
        acc(2, :, :, :) > 0.0_wp)
      call h5_write_cell_field(file, trim(paths(1 + d)), grid, field)
    end do
  end subroutine write_cell_dump
end module mpm_output
