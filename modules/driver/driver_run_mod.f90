!> Run driver entry point. Placeholder: the lead developer replaces this file with the time loop.
module driver_run_mod
  use config_types, only: config_t
  use mpmice_log, only: log_info
  implicit none
  private

  public :: driver_run

contains

  !> Run the scene described by `cfg` (read from `source_file`), or continue it from
  !! `restart_file` ('' when not restarting). Placeholder: only logs what it would run.
  subroutine driver_run(cfg, source_file, restart_file)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    character(len=*), intent(in) :: source_file        !< case file the configuration came from
    character(len=*), intent(in) :: restart_file       !< checkpoint to continue, '' if none
    call log_info('mpmice: scene ''' // trim(cfg%run%scene) // ''' from ' // trim(source_file) &
      // ': the time loop is not available in this build')
    if (len_trim(restart_file) > 0) call log_info('mpmice: restart from ' // trim(restart_file))
  end subroutine driver_run
end module driver_run_mod
