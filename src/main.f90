!> MPMICE executable: parse the command line and run the driver.
program mpmice
  use mpmice_app, only: app_run
  implicit none
  call app_run()
end program mpmice
