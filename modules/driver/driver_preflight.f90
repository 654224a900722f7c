!> Checks a run makes before it writes or allocates anything (docs/batch.md "Before a run
!! writes"): will the scene fit in memory, and can the output folder be used.
!!
!! Memory: an upper-bound estimate per rank, from the cells of the rank's block (ghost layers
!! included) and the particles the solids will seed into it, compared with the memory the
!! node can give (`MemAvailable` of /proc/meminfo, or less under a cgroup limit) for all the
!! ranks of the node together. Measured peak resident memory per cell (1 rank, 2D and 3D, the
!! scenes of namelists/, `/usr/bin/time -f %M` between two grid sizes): heat conduction 209-222
!! B, ice with one fluid 577-615 B, mpmice with one fluid and one solid 1680-1870 B; 456 B per
!! particle (mpm_column_2d, 1x1 against 4x4 particles per cell). The estimate rounds these up
!! (`bytes_per_cell`, `bytes_per_particle`) and adds a fixed `rank_overhead` for MPI, hypre and
!! HDF5.
!!
!! Output folder: its path must be usable (no component longer than 255 characters, no part of
!! it a file, writable), and it must not hold another run's output: a file `<name>.used.nml`,
!! `<name>.status`, `<name>.xmf` or `<name>_000000.h5` of the same `&run name` (every run writes
!! the first three, every fresh run the last). A restart that continues in its checkpoint's
!! folder, and a run with `&run overwrite = .true.`, may use such a folder. Otherwise the echo
!! `<name>.used.nml` is created exclusively (`status='new'`, O_EXCL), so that of two runs
!! started into one folder at the same moment only one goes on.
module driver_preflight
  use, intrinsic :: iso_fortran_env, only: int64
  use parallel_comm, only: MPI_Comm, comm_rank, node_sum, max_location, bcast
  use mpmice_kinds, only: wp, path_len, msg_len
  use mpmice_errors, only: int_text
  use config_types, only: config_t, solid_params_t, particles_per_cell_used
  use config_text, only: ints_repr, quoted
  use parallel_domain, only: domain_t, domain_init, domain_free
  use driver_balance, only: run_block_cells
  use io_files, only: io_join_path, io_file_exists, io_dirname, io_dump_stem
  use io_paths, only: io_check_output_directory, io_make_output_directory
  implicit none
  private

  public :: preflight_memory, preflight_output_dir, estimate_block_bytes

  real(wp), parameter :: gib = 1024.0_wp**3                 !< bytes in a GiB
  real(wp), parameter :: rank_overhead = 64.0_wp * 1024.0_wp**2 !< per rank: MPI, hypre, HDF5 [B]
  real(wp), parameter :: bytes_per_particle = 600.0_wp      !< per particle, upper bound [B]

contains

  !> Collective over `comm`: `stat` = 1 and `errmsg` (one line, every rank) when the ranks of a
  !! node would need more memory than the node has available. Writes nothing; a machine whose
  !! available memory cannot be read is not checked.
  subroutine preflight_memory(cfg, comm, stat, errmsg)
    type(config_t), intent(in) :: cfg                     !< validated configuration
    type(MPI_Comm), intent(in) :: comm                    !< communicator of the run
    integer, intent(out) :: stat                          !< 0 fits, 1 refused
    character(len=:), allocatable, intent(out) :: errmsg  !< error line
    type(domain_t) :: dom
    real(wp) :: mine, node_bytes, available, worst_in(2), worst(2), values(3)
    integer :: node_rank, node_ranks, rank, owner

    stat = 0
    errmsg = ''
    rank = comm_rank(comm)
    call domain_init(dom, comm, cfg%grid%ncells, cfg%grid%periodic, cfg%grid%ghost_width, &
      cfg%grid%dims, run_block_cells(cfg, comm))
    mine = estimate_block_bytes(cfg, dom)
    call domain_free(dom)

    call node_sum(comm, mine, node_bytes, node_rank, node_ranks)

    ! the node most over its memory (need / available), as seen by its first rank
    worst_in = [0.0_wp, real(rank, wp)]
    available = -1.0_wp
    if (node_rank == 0) then
      available = available_memory()
      if (available > 0.0_wp) worst_in(1) = node_bytes / available
    end if
    call max_location(comm, worst_in, worst)
    if (worst(1) <= 1.0_wp) return

    owner = nint(worst(2))
    values = [mine, available, real(node_ranks, wp)]
    call bcast(comm, values, owner)
    stat = 1
    errmsg = 'mpmice: input error: &grid ncells = ' // ints_repr(cfg%grid%ncells) // &
      ': the run needs about ' // gib_text(values(1)) // ' of memory per rank (' // &
      gib_text(worst(1) * values(2)) // ' for the ' // int_text(nint(values(3))) // &
      ' ranks of a node) but the node has ' // gib_text(values(2)) // ' available ' // &
      '(MemAvailable or the cgroup limit); use fewer cells or particles, or more nodes'
  end subroutine preflight_memory

  !> Upper-bound estimate of the memory [B] of the block `dom` owns for the scene of `cfg`:
  !! `bytes_per_cell` times its cells with ghost layers, `bytes_per_particle` times the
  !! particles the solids seed into it, plus `rank_overhead`.
  function estimate_block_bytes(cfg, dom) result(bytes)
    type(config_t), intent(in) :: cfg    !< validated configuration
    type(domain_t), intent(in) :: dom    !< decomposition
    real(wp) :: bytes
    real(wp) :: cells, particles
    integer :: k
    cells = product(real(dom%hi - dom%lo + 1 + 2 * dom%ng, wp))
    particles = 0.0_wp
    do k = 1, cfg%nsolids
      particles = particles + block_particles(cfg, dom, cfg%solids(k))
    end do
    bytes = rank_overhead + bytes_per_cell(cfg) * cells + bytes_per_particle * particles
  end function estimate_block_bytes

  !> Upper bound of the memory per grid cell [B] of the scene (see the module header).
  pure function bytes_per_cell(cfg) result(bytes)
    type(config_t), intent(in) :: cfg  !< configuration
    real(wp) :: bytes
    select case (trim(cfg%run%scene))
    case ('heat_conduction')
      bytes = 300.0_wp
    case ('ice')
      bytes = 400.0_wp + 400.0_wp * real(cfg%nfluids, wp)
    case ('mpm')
      bytes = 300.0_wp + 400.0_wp * real(cfg%nsolids, wp)
    case default
      bytes = 1200.0_wp + 500.0_wp * real(cfg%nfluids + cfg%nsolids, wp)
    end select
  end function bytes_per_cell

  !> Particles solid `s` seeds into the block of `dom` (at most): the particles per cell times
  !! the block's cells inside the solid's bounding box (a box without rotation, a polygon's
  !! x-y extent; the whole domain for other shapes), one cell of margin on each side.
  function block_particles(cfg, dom, s) result(n)
    type(config_t), intent(in) :: cfg        !< configuration
    type(domain_t), intent(in) :: dom        !< decomposition
    type(solid_params_t), intent(in) :: s    !< the solid
    real(wp) :: n
    real(wp) :: lo(3), hi(3), dx(3), block_lo, block_hi, overlap
    integer :: ppc(3), d
    lo = cfg%grid%lower
    hi = cfg%grid%upper
    if (trim(s%shape) == 'box' .and. s%rotation_deg == 0.0_wp) then
      lo = s%lower
      hi = s%upper
    else if (trim(s%shape) == 'polygon' .and. s%npoints > 0) then
      lo(1:2) = [minval(s%polygon_x(1:s%npoints)), minval(s%polygon_y(1:s%npoints))]
      hi(1:2) = [maxval(s%polygon_x(1:s%npoints)), maxval(s%polygon_y(1:s%npoints))]
    end if
    dx = (cfg%grid%upper - cfg%grid%lower) / real(cfg%grid%ncells, wp)
    ppc = particles_per_cell_used(s, cfg%grid%ncells)
    n = 1.0_wp
    do d = 1, 3
      if (.not. dom%active(d)) cycle
      block_lo = cfg%grid%lower(d) + real(dom%lo(d) - 1, wp) * dx(d)
      block_hi = cfg%grid%lower(d) + real(dom%hi(d), wp) * dx(d)
      overlap = min(hi(d) + dx(d), block_hi) - max(lo(d) - dx(d), block_lo)
      n = n * max(overlap / dx(d), 0.0_wp) * real(ppc(d), wp)
    end do
  end function block_particles

  !> Memory the node can give [B]: `MemAvailable` of /proc/meminfo, lowered to what a cgroup
  !! (v2 `memory.max`, or v1 `memory.limit_in_bytes`) leaves; -1 when none can be read.
  function available_memory() result(bytes)
    real(wp) :: bytes
    real(wp) :: limit, used
    bytes = meminfo_value('MemAvailable:')
    limit = file_number('/sys/fs/cgroup/memory.max')
    used = file_number('/sys/fs/cgroup/memory.current')
    if (limit <= 0.0_wp) then
      limit = file_number('/sys/fs/cgroup/memory/memory.limit_in_bytes')
      used = file_number('/sys/fs/cgroup/memory/memory.usage_in_bytes')
    end if
    ! cgroup v1 reports "no limit" as a huge number
    if (limit > 0.0_wp .and. limit < 2.0_wp**60) then
      if (bytes > 0.0_wp) then
        bytes = min(bytes, limit - max(used, 0.0_wp))
      else
        bytes = limit - max(used, 0.0_wp)
      end if
    end if
  end function available_memory

  !> The value [B] of the /proc/meminfo line starting with `key` (given in kB); -1 if missing.
  function meminfo_value(key) result(bytes)
    character(len=*), intent(in) :: key  !< e.g. 'MemAvailable:'
    real(wp) :: bytes
    character(len=256) :: line
    integer :: unit, ios
    integer(int64) :: kib
    bytes = -1.0_wp
    open(newunit=unit, file='/proc/meminfo', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, key) == 1) then
        read(line(len(key) + 1:), *, iostat=ios) kib
        if (ios == 0) bytes = 1024.0_wp * real(kib, wp)
        exit
      end if
    end do
    close(unit)
  end function meminfo_value

  !> The number in the one-line file `path`; -1 if missing or not a number (e.g. "max").
  function file_number(path) result(value)
    character(len=*), intent(in) :: path  !< file
    real(wp) :: value
    integer :: unit, ios
    integer(int64) :: n
    value = -1.0_wp
    open(newunit=unit, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    read(unit, *, iostat=ios) n
    if (ios == 0) value = real(n, wp)
    close(unit)
  end function file_number

  !> Bytes as GiB with 3 significant digits.
  function gib_text(bytes) result(text)
    real(wp), intent(in) :: bytes  !< amount [B]
    character(len=:), allocatable :: text
    character(len=32) :: buffer
    write(buffer, '(es10.3)') bytes / gib
    if (bytes / gib < 1.0e4_wp) write(buffer, '(f10.2)') bytes / gib
    text = trim(adjustl(buffer)) // ' GiB'
  end function gib_text

  !> Rank 0 of the run: make the output folder ready, or say why it cannot be used. `stat` = 1
  !! and `errmsg` (one line) when its path cannot be used or created, or when it holds another
  !! run's output (see the module header) and neither `&run overwrite` is set nor the run is a
  !! restart continuing in its checkpoint's folder (`restart_file` not '' and in that folder).
  !! Nothing is created when the folder is refused.
  subroutine preflight_output_dir(cfg, restart_file, stat, errmsg)
    type(config_t), intent(in) :: cfg                     !< validated configuration
    character(len=*), intent(in) :: restart_file          !< checkpoint continued, '' if none
    integer, intent(out) :: stat                          !< 0 ready
    character(len=:), allocatable, intent(out) :: errmsg  !< error line
    character(len=:), allocatable :: dir, reason, found, used
    character(len=path_len), allocatable :: markers(:)
    character(len=msg_len) :: iomsg
    integer :: k, unit, ios
    logical :: own_folder

    dir = trim(cfg%run%output_dir)
    call io_check_output_directory(dir, stat, reason)
    if (stat /= 0) then
      errmsg = dir_error(dir, reason)
      return
    end if
    own_folder = .false.
    if (len_trim(restart_file) > 0) own_folder = io_dirname(restart_file) == dir
    if (.not. (own_folder .or. cfg%run%overwrite)) then
      markers = [character(len=path_len) :: trim(cfg%run%name) // '.used.nml', &
        trim(cfg%run%name) // '.status', trim(cfg%run%name) // '.xmf', &
        io_dump_stem(cfg%run%name, 0) // '.h5']
      found = ''
      do k = 1, size(markers)
        if (io_file_exists(io_join_path(dir, markers(k)))) then
          found = trim(markers(k))
          exit
        end if
      end do
      if (len(found) > 0) then
        stat = 1
        errmsg = used_error(dir, trim(cfg%run%name), found)
        return
      end if
    end if
    call io_make_output_directory(dir, stat, reason)
    if (stat /= 0) then
      errmsg = dir_error(dir, reason)
    else if (.not. (own_folder .or. cfg%run%overwrite)) then
      ! claim the folder: create the echo exclusively (O_EXCL), so that of two runs started
      ! into it at the same moment only one goes on; the caller then writes the echo into it
      used = io_join_path(dir, trim(cfg%run%name) // '.used.nml')
      open(newunit=unit, file=used, status='new', action='write', iostat=ios, iomsg=iomsg)
      if (ios == 0) then
        close(unit)
      else
        stat = 1
        if (io_file_exists(used)) then
          errmsg = used_error(dir, trim(cfg%run%name), trim(cfg%run%name) // '.used.nml')
        else
          errmsg = dir_error(dir, trim(iomsg))
        end if
      end if
    end if
  end subroutine preflight_output_dir

  !> The error line of an output folder that holds the output of a run named `name`.
  function used_error(dir, name, found) result(text)
    character(len=*), intent(in) :: dir    !< the folder
    character(len=*), intent(in) :: name   !< `&run name`
    character(len=*), intent(in) :: found  !< the file that shows it
    character(len=:), allocatable :: text
    text = 'mpmice: input error: &run output_dir = ' // quoted(dir) // ' already holds the ' // &
      'output of a run named ' // quoted(name) // ' (' // found // '); choose another ' // &
      'output_dir or name, remove that run''s files, continue it with --restart, or replace ' &
      // 'them with --set ''&run overwrite = .true. /'''
  end function used_error

  !> The error line of an output folder that cannot be used.
  function dir_error(dir, reason) result(text)
    character(len=*), intent(in) :: dir     !< the folder
    character(len=*), intent(in) :: reason  !< why
    character(len=:), allocatable :: text
    text = 'mpmice: error: cannot write to &run output_dir = ' // quoted(dir) // ': ' // reason
  end function dir_error
end module driver_preflight
