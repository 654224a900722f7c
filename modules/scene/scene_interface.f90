!> The interface every scene (heat conduction, ICE, MPM, MPMICE) implements for the generic time
!! loop of `driver_loop`.
!!
!! The loop owns the clock, output and checkpoint scheduling, failure detection, the wall-time stop,
!! progress and timers; a scene owns its state and physics. Contract:
!! * each scene has its own typed setup, `<scene>_setup(self, params, ctx)`, taking only its own
!!   parameter bundle (`scene_params`: the groups it reads) and the run's context
!!   (`scene_context_t`: decomposition, grid, stage timers), which the scene keeps in `ctx` for
!!   every later call; `driver_scene_params%scene_create` is the one place that picks the scene
!!   from the bundle and calls its setup. The setup allocates everything (no allocation inside the
!!   time loop afterwards) and sets the initial state; `restore` replaces the state by the one
!!   stored in a checkpoint;
!! * `stable_dt` returns the scene's stability limit [s] for the Courant number `cfl` the clock
!!   owns (the same on every rank; `huge` if none);
!! * `step` advances by `dt`; when it cannot (e.g. an implicit iteration did not converge) it
!!   returns `accepted = .false.` with the state unchanged, and the loop retries with a smaller dt;
!! * `write_state` writes its datasets into an open dump (`checkpoint = .false.`) or checkpoint
!!   (`.true.`: everything needed for a bitwise-identical continuation, under `/checkpoint/`);
!! * `output_layout` names the datasets of a dump for the XDMF file;
!! * `all_finite` is the local (this rank's) check that no state value is NaN or infinite;
!! * `health` (optional, collective) gives the run loop's stops (`driver_stops`) the solids'
!!   energy, the power of the loads on them and the particle counts; scenes without solids keep
!!   the default, which reports nothing (`has_solids = .false.`).
module scene_interface
  use mpmice_kinds, only: wp, i8, name_len
  use mpmice_timers, only: timer_set_t
  use parallel_domain, only: domain_t
  use grid_layout, only: grid_t
  use io_hdf5, only: h5_file_t
  use io_xdmf, only: xdmf_particles_t
  implicit none
  private

  public :: scene_t, scene_health_t, scene_context_t

  !> What every scene method works in: the run's decomposition, block geometry and stage timers,
  !! owned by the driver (`driver_loop%run_scene`) for the whole run; a scene's setup keeps it.
  type :: scene_context_t
    type(domain_t), pointer :: dom => null()        !< decomposition
    type(grid_t), pointer :: grid => null()         !< block geometry
    type(timer_set_t), pointer :: timers => null()  !< stage timers of the run
  end type scene_context_t

  !> What the run loop's stops read from a scene (global values, the same on every rank).
  type :: scene_health_t
    logical :: has_solids = .false.   !< the scene has deformable solids (the values below apply)
    real(wp) :: energy = 0.0_wp       !< kinetic + elastic strain energy of the solids [J]
    real(wp) :: load_power = 0.0_wp   !< power of gravity and surface loads on them [W]
    integer(i8) :: particles = 0_i8   !< particles in the domain
    integer(i8) :: lost = 0_i8        !< particles that left the domain since the run began
  end type scene_health_t

  !> A scene of the time loop.
  type, abstract :: scene_t
    type(scene_context_t) :: ctx  !< decomposition, grid and timers (set by the scene's setup)
  contains
    procedure(scene_dt_i), deferred :: stable_dt            !< stability limit of the next step [s]
    procedure(scene_step_i), deferred :: step               !< advance by dt
    procedure(scene_write_i), deferred :: write_state       !< datasets of a dump or checkpoint
    procedure(scene_restore_i), deferred :: restore         !< read the state of a checkpoint
    procedure(scene_layout_i), deferred :: output_layout    !< datasets of a dump (for XDMF)
    procedure(scene_finite_i), deferred :: all_finite       !< local NaN/Inf check
    procedure(scene_summary_i), deferred :: summary         !< log end-of-run statistics
    procedure(scene_free_i), deferred :: free               !< release everything
    procedure :: health => scene_no_health                  !< energy and particle counts
  end type scene_t

  abstract interface
    !> Stability limit of the next step [s], identical on every rank (huge if none).
    function scene_dt_i(self, cfl) result(dt)
      import :: scene_t, wp
      class(scene_t), intent(inout) :: self  !< scene
      real(wp), intent(in) :: cfl            !< Courant number (`&time cfl`, owned by the clock)
      real(wp) :: dt
    end function scene_dt_i

    !> Advance the state from `time` by `dt` [s]; `accepted = .false.` leaves the state unchanged.
    subroutine scene_step_i(self, time, dt, accepted)
      import :: scene_t, wp
      class(scene_t), intent(inout) :: self        !< scene
      real(wp), intent(in) :: time                 !< time at the start of the step [s]
      real(wp), intent(in) :: dt                   !< step [s]
      logical, intent(out) :: accepted             !< the step was taken
    end subroutine scene_step_i

    !> Write the scene's datasets into the open file (collective).
    subroutine scene_write_i(self, file, checkpoint)
      import :: scene_t, h5_file_t
      class(scene_t), intent(inout) :: self  !< scene
      type(h5_file_t), intent(in) :: file    !< open dump or checkpoint
      logical, intent(in) :: checkpoint      !< write the full restart state
    end subroutine scene_write_i

    !> Read the state from an open checkpoint (collective).
    subroutine scene_restore_i(self, file)
      import :: scene_t, h5_file_t
      class(scene_t), intent(inout) :: self  !< scene
      type(h5_file_t), intent(in) :: file    !< open checkpoint
    end subroutine scene_restore_i

    !> Cell datasets and particle sets (size 0 when none) that `write_state` puts in a dump, for
    !! the XDMF description.
    subroutine scene_layout_i(self, cell_paths, particle_sets)
      import :: scene_t, name_len, xdmf_particles_t
      class(scene_t), intent(in) :: self                                 !< scene
      character(len=name_len), allocatable, intent(out) :: cell_paths(:)  !< cell dataset paths
      type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    end subroutine scene_layout_i

    !> True when this rank's state holds no NaN or infinity.
    function scene_finite_i(self) result(finite)
      import :: scene_t
      class(scene_t), intent(in) :: self  !< scene
      logical :: finite
    end function scene_finite_i

    !> Log the scene's end-of-run statistics (collective; rank 0 prints).
    subroutine scene_summary_i(self)
      import :: scene_t
      class(scene_t), intent(inout) :: self  !< scene
    end subroutine scene_summary_i

    !> Release the state.
    subroutine scene_free_i(self)
      import :: scene_t
      class(scene_t), intent(inout) :: self  !< scene
    end subroutine scene_free_i
  end interface

contains

  !> Default `health`: a scene without solids reports nothing.
  subroutine scene_no_health(self, time, health)
    class(scene_t), intent(inout) :: self          !< scene
    real(wp), intent(in) :: time                   !< time of the state [s]
    type(scene_health_t), intent(out) :: health    !< nothing (has_solids = .false.)
    if (.false.) health%energy = time + merge(1.0_wp, 0.0_wp, same_type_as(self, self))
  end subroutine scene_no_health
end module scene_interface
