!> Run-loop stops for runs that go wrong without a non-finite value: energy growth of the solids,
!! particles lost through the domain faces, and a collapsed time step (`&run max_energy_growth`,
!! `max_particle_loss_fraction`, `min_dt_ratio`; docs/accuracy.md). All are off by default and
!! then cost nothing; `driver_loop` stops a run they flag with state `failed` and exit status 3.
!!
!! * Energy: E = kinetic + elastic strain energy of the deformable solids (`scene_t%health`).
!!   Reference R(t) = E(0) + W(t), W the work put in by gravity and the loads on the solids
!!   (`&solid traction`, `&boundary solid = 'traction'`): the positive part of their power,
!!   integrated with the trapezoidal rule over the steps. A passive solid (elastic, plastic,
!!   damped) cannot hold more than R; the stop fires when E > max_energy_growth R. Not counted
!!   in W: prescribed-velocity walls, rigid bodies and, in a coupled scene, the fluids' forces
!!   on the solid (pressure gradient, drag).
!!   While R = 0 (a solid at rest without loads) there is nothing to compare with.
!! * Particle loss: removed / (in the domain + removed) > max_particle_loss_fraction.
!! * Step collapse: the scene's stability limit below min_dt_ratio times the reference limit, the
!!   first step's limit capped by `&time dt_max`.
!! The references (E(0), W, the first step's limit) travel in checkpoints with the clock.
module driver_stops
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: int_text, real_short_text
  use config_types, only: config_t
  use driver_clock, only: clock_t
  use scene_interface, only: scene_t, scene_health_t
  implicit none
  private

  public :: stops_watch_state, stops_start, stops_check_dt, stops_check_state

contains

  !> True when a stop needs the scene's health after every step (energy or particle loss).
  pure logical function stops_watch_state(cfg)
    type(config_t), intent(in) :: cfg  !< validated configuration
    stops_watch_state = cfg%run%max_energy_growth > 0.0_wp .or. &
      cfg%run%max_particle_loss_fraction < 1.0_wp
  end function stops_watch_state

  !> At the start of a run (or a restart): set the energy reference E(0) when it is not set yet
  !! and return the load power of the current state (collective).
  subroutine stops_start(scene, clock, power)
    class(scene_t), intent(inout) :: scene   !< scene
    type(clock_t), intent(inout) :: clock    !< run clock (carries the references)
    real(wp), intent(out) :: power           !< power of gravity and loads now [W]
    type(scene_health_t) :: health
    call scene%health(clock%time, health)
    if (clock%energy_reference < 0.0_wp) then
      clock%energy_reference = health%energy
      clock%load_work = 0.0_wp
    end if
    power = health%load_power
  end subroutine stops_start

  !> Step-collapse check before a step with stability limit `dt_limit` [s]; the first call sets
  !! the reference. Returns the reason, '' when the step may be taken.
  function stops_check_dt(cfg, clock, dt_limit) result(reason)
    type(config_t), intent(in) :: cfg        !< validated configuration
    type(clock_t), intent(inout) :: clock    !< run clock (carries the reference)
    real(wp), intent(in) :: dt_limit         !< the scene's stability limit [s]
    character(len=path_len) :: reason
    reason = ''
    if (cfg%run%min_dt_ratio <= 0.0_wp) return
    if (clock%dt_reference <= 0.0_wp) clock%dt_reference = min(dt_limit, clock%dt_max)
    if (dt_limit < cfg%run%min_dt_ratio * clock%dt_reference) reason = 'time step collapsed: ' &
      // 'stability limit ' // real_short_text(dt_limit) // ' s below &run min_dt_ratio = ' // &
      real_short_text(cfg%run%min_dt_ratio) // ' x the reference ' // &
      real_short_text(clock%dt_reference) // ' s at step ' // int_text(clock%step + 1) // &
      ', t = ' // real_short_text(clock%time) // ' s'
  end function stops_check_dt

  !> Energy-growth and particle-loss checks after the step of `clock%dt` that ended at
  !! `clock%time` (collective). `power` is the load power before the step on entry, after it on
  !! exit; `peak` the largest E / R so far. `reason` is '' when the run may go on.
  subroutine stops_check_state(scene, cfg, clock, power, peak, reason)
    class(scene_t), intent(inout) :: scene        !< scene
    type(config_t), intent(in) :: cfg             !< validated configuration
    type(clock_t), intent(inout) :: clock         !< run clock (carries the references)
    real(wp), intent(inout) :: power              !< load power [W]
    real(wp), intent(inout) :: peak               !< largest energy / reference so far
    character(len=path_len), intent(out) :: reason !< why the run must stop, '' if it need not
    type(scene_health_t) :: health
    real(wp) :: reference, lost_fraction
    reason = ''
    call scene%health(clock%time, health)
    if (.not. health%has_solids) return
    clock%load_work = clock%load_work + 0.5_wp * clock%dt * (max(power, 0.0_wp) + &
      max(health%load_power, 0.0_wp))
    power = health%load_power
    if (cfg%run%max_energy_growth > 0.0_wp) then
      reference = clock%energy_reference + clock%load_work
      if (reference > 0.0_wp) peak = max(peak, health%energy / reference)
      if (reference > 0.0_wp .and. health%energy > cfg%run%max_energy_growth * reference) then
        reason = 'energy growth: solid energy ' // real_short_text(health%energy) // &
          ' J > &run max_energy_growth = ' // real_short_text(cfg%run%max_energy_growth) // &
          ' x the reference ' // real_short_text(reference) // ' J (initial ' // &
          real_short_text(clock%energy_reference) // ' J + work of gravity and loads) at step ' &
          // int_text(clock%step) // ', t = ' // real_short_text(clock%time) // ' s'
        return
      end if
    end if
    if (cfg%run%max_particle_loss_fraction < 1.0_wp .and. health%lost > 0) then
      lost_fraction = real(health%lost, wp) / real(health%particles + health%lost, wp)
      if (lost_fraction > cfg%run%max_particle_loss_fraction) reason = 'particle loss: ' // &
        int_text(int(health%lost)) // ' of ' // int_text(int(health%particles + health%lost)) &
        // ' particles left the domain (fraction ' // real_short_text(lost_fraction) // &
        ' > &run max_particle_loss_fraction = ' // &
        real_short_text(cfg%run%max_particle_loss_fraction) // ') by step ' // &
        int_text(clock%step) // ', t = ' // real_short_text(clock%time) // ' s'
    end if
  end subroutine stops_check_state
end module driver_stops
