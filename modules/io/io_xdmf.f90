!> XDMF (version 2 syntax, read by ParaView's XDMF and XDMF3 readers and by VisIt) descriptions
!! of the HDF5 dumps: one `.xmf` per dump and a time-series `.xmf` collecting all dumps.
!!
!! The grid is a `3DCoRectMesh` with `ORIGIN_DXDYDZ` geometry whatever the number of active
!! dimensions: an inactive dimension is one cell thick. XDMF lists dimensions slowest first, so
!! topology, origin, spacing and attribute dimensions are written in the order z, y, x (k, j, i),
!! which matches the C order of the HDF5 datasets (see `io_hdf5_fields`). Cell fields are
!! `Center="Cell"` attributes. Particle sets, when given, are `Polyvertex` grids with `X_Y_Z`
!! geometry from the datasets `<group>/x`, `<group>/y` and `<group>/z` (all three must exist) and
!! node-centred attributes; a dump with particles is a spatial collection of the cell grid and
!! one grid per non-empty particle set.
!!
!! The time series is rewritten at each dump with full copies of the dump grids (no XInclude,
!! which not every reader follows). Dumps whose time is not earlier than the new dump's time
!! are dropped first, so a run restarted from a checkpoint continues its series cleanly.
!! These routines write files from the calling rank only: call them on rank 0 after the dump's
!! HDF5 file is closed.
module io_xdmf
  use mpmice_kinds, only: wp, i8, name_len, path_len, msg_len
  use mpmice_errors, only: fatal, int_text, real_text
  use grid_layout, only: grid_t
  use io_files, only: io_file_exists, io_rename
  use io_write_failure, only: io_write_failed, io_close_checked
  implicit none
  private

  public :: xdmf_particles_t, xdmf_write_dump, xdmf_update_series

  !> A particle set to show in a dump: a group of 1-D particle datasets of equal length.
  type :: xdmf_particles_t
    character(len=path_len) :: group = ''     !< HDF5 group, e.g. `particles/sand`
    integer(i8) :: count = 0_i8               !< particles in the set (all ranks)
    character(len=name_len), allocatable :: fields(:)      !< real(wp) datasets in the group
    character(len=name_len), allocatable :: int_fields(:)  !< integer(i8) datasets in the group
  end type xdmf_particles_t

  character(len=*), parameter :: begin_mark = '<!-- mpmice-dump-begin time='  !< block start
  character(len=*), parameter :: end_mark = '<!-- mpmice-dump-end -->'        !< block end

contains

  !> Write the XDMF file `path_xmf` describing the dump `h5_name` (the HDF5 file's name relative
  !! to the folder of `path_xmf`, normally its basename).
  subroutine xdmf_write_dump(path_xmf, h5_name, grid, time, cell_fields, particles)
    character(len=*), intent(in) :: path_xmf            !< XDMF file to write
    character(len=*), intent(in) :: h5_name             !< HDF5 file, relative to path_xmf
    type(grid_t), intent(in) :: grid                    !< any block of the grid
    real(wp), intent(in) :: time                        !< simulated time [s]
    character(len=*), intent(in) :: cell_fields(:)      !< cell dataset paths, e.g. `cell/pressure`
    type(xdmf_particles_t), intent(in), optional :: particles(:) !< particle sets to show
    integer :: unit, stat, p
    character(len=msg_len) :: msg
    character(len=:), allocatable :: reason
    logical :: collection

    collection = .false.
    if (present(particles)) collection = any(particles%count > 0_i8)
    open(newunit=unit, file=trim(path_xmf), status='replace', action='write', iostat=stat, &
      iomsg=msg)
    if (stat /= 0) call write_failed(path_xmf, 'open', msg)
    call put(unit, path_xmf, '<?xml version="1.0" ?>')
    call put(unit, path_xmf, '<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>')
    call put(unit, path_xmf, '<Xdmf Version="2.0">')
    call put(unit, path_xmf, '  <Domain>')
    call put(unit, path_xmf, begin_mark // real_text(time) // ' -->')
    if (collection) then
      call put(unit, path_xmf, '    <Grid Name="' // xml_text(stem(h5_name)) &
        // '" GridType="Collection" CollectionType="Spatial">')
      call put(unit, path_xmf, '      <Time Value="' // real_text(time) // '"/>')
      call write_cell_grid(unit, path_xmf, '      ', 'cells', h5_name, grid, time, cell_fields, &
        .false.)
      do p = 1, size(particles)
        if (particles(p)%count > 0_i8) then
          call write_particle_grid(unit, path_xmf, '      ', h5_name, particles(p))
        end if
      end do
      call put(unit, path_xmf, '    </Grid>')
    else
      call write_cell_grid(unit, path_xmf, '    ', stem(h5_name), h5_name, grid, time, &
        cell_fields, .true.)
    end if
    call put(unit, path_xmf, end_mark)
    call put(unit, path_xmf, '  </Domain>')
    call put(unit, path_xmf, '</Xdmf>')
    call io_close_checked(unit, path_xmf, stat, reason)
    if (stat /= 0) call write_failed(path_xmf, 'close', reason)
  end subroutine xdmf_write_dump

  !> Add the dump described by `dump_xmf` (written by `xdmf_write_dump`, at `time`) to the
  !! temporal collection `series_xmf`, dropping listed dumps at or after `time`. Both files must
  !! sit in the same folder as the HDF5 files. The series is written to `series_xmf.tmp` and
  !! renamed, so a reader never sees a half-written file.
  subroutine xdmf_update_series(series_xmf, dump_xmf, time)
    character(len=*), intent(in) :: series_xmf  !< time-series file (created if missing)
    character(len=*), intent(in) :: dump_xmf    !< XDMF file of the new dump
    real(wp), intent(in) :: time                !< simulated time of the new dump [s]
    character(len=:), allocatable :: tmp
    integer :: out, stat
    character(len=msg_len) :: msg
    character(len=:), allocatable :: reason

    tmp = trim(series_xmf) // '.tmp'
    open(newunit=out, file=tmp, status='replace', action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) call write_failed(tmp, 'open', msg)
    call put(out, tmp, '<?xml version="1.0" ?>')
    call put(out, tmp, '<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>')
    call put(out, tmp, '<Xdmf Version="2.0">')
    call put(out, tmp, '  <Domain>')
    call put(out, tmp, '    <Grid Name="time_series" GridType="Collection" ' &
      // 'CollectionType="Temporal">')
    if (io_file_exists(series_xmf)) call copy_blocks(out, tmp, series_xmf, time, .true.)
    call copy_blocks(out, tmp, dump_xmf, time, .false.)
    call put(out, tmp, '    </Grid>')
    call put(out, tmp, '  </Domain>')
    call put(out, tmp, '</Xdmf>')
    call io_close_checked(out, tmp, stat, reason)
    if (stat /= 0) call write_failed(tmp, 'close', reason)
    call io_rename(tmp, series_xmf)
  end subroutine xdmf_update_series

  !> Copy the marked dump blocks of `source` to `out`: the blocks earlier than `time` when
  !! `earlier_only` (copying from the series), all blocks indented two more blanks otherwise
  !! (copying from a dump file).
  subroutine copy_blocks(out, out_path, source, time, earlier_only)
    integer, intent(in) :: out               !< open output unit
    character(len=*), intent(in) :: out_path !< output file (for messages)
    character(len=*), intent(in) :: source   !< XDMF file to copy from
    real(wp), intent(in) :: time             !< time of the new dump [s]
    logical, intent(in) :: earlier_only      !< keep only blocks with time < `time`
    character(len=:), allocatable :: line
    character(len=msg_len) :: msg
    integer :: in, stat
    logical :: inside, keep
    real(wp) :: block_time

    open(newunit=in, file=trim(source), status='old', action='read', iostat=stat, iomsg=msg)
    if (stat /= 0) call fatal('xdmf_update_series: cannot open ' // trim(source) // ': ' &
      // trim(msg))
    inside = .false.
    keep = .false.
    do
      call read_line(in, line, stat)
      if (stat /= 0) exit
      if (.not. inside) then
        if (index(adjustl(line), begin_mark) /= 1) cycle
        inside = .true.
        block_time = marked_time(trim(adjustl(line)), source)
        keep = (.not. earlier_only) .or. block_time < time
      end if
      ! Blocks from a dump file get two more blanks; blocks of the series are already indented.
      if (keep .and. earlier_only) call put(out, out_path, line)
      if (keep .and. .not. earlier_only) call put(out, out_path, '  ' // line)
      if (index(adjustl(line), end_mark) == 1) inside = .false.
    end do
    if (.not. is_iostat_end(stat)) call fatal('xdmf_update_series: cannot read ' &
      // trim(source))
    if (inside) call fatal('xdmf_update_series: unterminated dump block in ' // trim(source))
    close(in)
  end subroutine copy_blocks

  !> Uniform 3DCoRectMesh grid of the cells with one attribute per cell field.
  subroutine write_cell_grid(unit, path, indent, name, h5_name, grid, time, cell_fields, &
      with_time)
    integer, intent(in) :: unit                   !< open output unit
    character(len=*), intent(in) :: path          !< output file (for messages)
    character(len=*), intent(in) :: indent        !< leading blanks
    character(len=*), intent(in) :: name          !< grid name
    character(len=*), intent(in) :: h5_name       !< HDF5 file
    type(grid_t), intent(in) :: grid              !< any block of the grid
    real(wp), intent(in) :: time                  !< simulated time [s]
    character(len=*), intent(in) :: cell_fields(:) !< cell dataset paths
    logical, intent(in) :: with_time              !< write the Time element here
    character(len=:), allocatable :: cell_dims
    integer :: f
    cell_dims = int_text(grid%ncells(3)) // ' ' // int_text(grid%ncells(2)) // ' ' &
      // int_text(grid%ncells(1))
    call put(unit, path, indent // '<Grid Name="' // xml_text(name) // '" GridType="Uniform">')
    if (with_time) call put(unit, path, indent // '  <Time Value="' // real_text(time) // '"/>')
    call put(unit, path, indent // '  <Topology TopologyType="3DCoRectMesh" Dimensions="' &
      // int_text(grid%ncells(3) + 1) // ' ' // int_text(grid%ncells(2) + 1) // ' ' &
      // int_text(grid%ncells(1) + 1) // '"/>')
    call put(unit, path, indent // '  <Geometry GeometryType="ORIGIN_DXDYDZ">')
    call put(unit, path, indent // '    <DataItem Name="Origin" Dimensions="3" ' &
      // 'NumberType="Float" Precision="8" Format="XML">' // real_text(grid%lower(3)) // ' ' &
      // real_text(grid%lower(2)) // ' ' // real_text(grid%lower(1)) // '</DataItem>')
    call put(unit, path, indent // '    <DataItem Name="Spacing" Dimensions="3" ' &
      // 'NumberType="Float" Precision="8" Format="XML">' // real_text(grid%dx(3)) // ' ' &
      // real_text(grid%dx(2)) // ' ' // real_text(grid%dx(1)) // '</DataItem>')
    call put(unit, path, indent // '  </Geometry>')
    do f = 1, size(cell_fields)
      call put(unit, path, indent // '  <Attribute Name="' &
        // xml_text(field_label(cell_fields(f))) // '" AttributeType="Scalar" Center="Cell">')
      call put(unit, path, indent // '    ' // data_item(cell_dims, 'Float', h5_name, &
        cell_fields(f)))
      call put(unit, path, indent // '  </Attribute>')
    end do
    call put(unit, path, indent // '</Grid>')
  end subroutine write_cell_grid

  !> Polyvertex grid of one particle set.
  subroutine write_particle_grid(unit, path, indent, h5_name, set)
    integer, intent(in) :: unit                   !< open output unit
    character(len=*), intent(in) :: path          !< output file (for messages)
    character(len=*), intent(in) :: indent        !< leading blanks
    character(len=*), intent(in) :: h5_name       !< HDF5 file
    type(xdmf_particles_t), intent(in) :: set     !< particle set
    character(len=:), allocatable :: n, group
    integer :: f
    n = int_text(set%count)
    group = trim(set%group)
    call put(unit, path, indent // '<Grid Name="' // xml_text(field_label(group)) &
      // '" GridType="Uniform">')
    call put(unit, path, indent // '  <Topology TopologyType="Polyvertex" NumberOfElements="' &
      // n // '" NodesPerElement="1"/>')
    call put(unit, path, indent // '  <Geometry GeometryType="X_Y_Z">')
    call put(unit, path, indent // '    ' // data_item(n, 'Float', h5_name, group // '/x'))
    call put(unit, path, indent // '    ' // data_item(n, 'Float', h5_name, group // '/y'))
    call put(unit, path, indent // '    ' // data_item(n, 'Float', h5_name, group // '/z'))
    call put(unit, path, indent // '  </Geometry>')
    if (allocated(set%fields)) then
      do f = 1, size(set%fields)
        call put_attribute(set%fields(f), 'Float')
      end do
    end if
    if (allocated(set%int_fields)) then
      do f = 1, size(set%int_fields)
        call put_attribute(set%int_fields(f), 'Int')
      end do
    end if
    call put(unit, path, indent // '</Grid>')
  contains
    !> One node-centred scalar attribute.
    subroutine put_attribute(field, number_type)
      character(len=*), intent(in) :: field        !< dataset name in the group
      character(len=*), intent(in) :: number_type  !< XDMF NumberType
      call put(unit, path, indent // '  <Attribute Name="' // xml_text(trim(field)) &
        // '" AttributeType="Scalar" Center="Node">')
      call put(unit, path, indent // '    ' // data_item(n, number_type, h5_name, &
        group // '/' // trim(field)))
      call put(unit, path, indent // '  </Attribute>')
    end subroutine put_attribute
  end subroutine write_particle_grid

  !> `<DataItem ...>file.h5:/path</DataItem>` for an 8-byte HDF5 dataset.
  function data_item(dims, number_type, h5_name, dataset) result(text)
    character(len=*), intent(in) :: dims         !< XDMF dimensions, slowest first
    character(len=*), intent(in) :: number_type  !< Float or Int
    character(len=*), intent(in) :: h5_name      !< HDF5 file
    character(len=*), intent(in) :: dataset      !< dataset path
    character(len=:), allocatable :: text
    text = '<DataItem Dimensions="' // dims // '" NumberType="' // number_type &
      // '" Precision="8" Format="HDF">' // xml_text(trim(h5_name)) // ':/' &
      // xml_text(clean_dataset(dataset)) // '</DataItem>'
  end function data_item

  !> Dataset path without leading `/` or blanks.
  pure function clean_dataset(dataset) result(clean)
    character(len=*), intent(in) :: dataset  !< dataset path
    character(len=:), allocatable :: clean
    clean = trim(adjustl(dataset))
    do while (len(clean) > 0)
      if (clean(1:1) /= '/') exit
      clean = clean(2:)
    end do
  end function clean_dataset

  !> Display name of a dataset: its path without the leading `cell/` or `particles/`, with `/`
  !! replaced by `_` (`cell/water/density` -> `water_density`).
  pure function field_label(dataset) result(label)
    character(len=*), intent(in) :: dataset  !< dataset or group path
    character(len=:), allocatable :: label
    integer :: i
    label = clean_dataset(dataset)
    if (index(label, 'cell/') == 1) label = label(6:)
    if (index(label, 'particles/') == 1) label = label(11:)
    do i = 1, len(label)
      if (label(i:i) == '/') label(i:i) = '_'
    end do
  end function field_label

  !> File name without folder and extension.
  pure function stem(file_name) result(text)
    character(len=*), intent(in) :: file_name  !< file name
    character(len=:), allocatable :: text
    integer :: slash, dot
    slash = index(trim(file_name), '/', back=.true.)
    text = trim(file_name(slash + 1:))
    dot = index(text, '.', back=.true.)
    if (dot > 1) text = text(1:dot - 1)
  end function stem

  !> Text with the XML special characters escaped.
  pure function xml_text(raw) result(text)
    character(len=*), intent(in) :: raw  !< unescaped text
    character(len=:), allocatable :: text
    character(len=*), parameter :: special = '&<>"'  !< the characters that are escaped
    !> their entities, in the order of `special`
    character(len=6), parameter :: entity(len(special)) = &
      [character(len=6) :: '&amp;', '&lt;', '&gt;', '&quot;']
    integer :: i, k
    text = ''
    do i = 1, len(raw)
      k = index(special, raw(i:i))
      if (k > 0) then
        text = text // trim(entity(k))
      else
        text = text // raw(i:i)
      end if
    end do
  end function xml_text

  !> Time of a block from its begin marker.
  function marked_time(line, source) result(time)
    character(len=*), intent(in) :: line    !< begin-marker line
    character(len=*), intent(in) :: source  !< file (for messages)
    real(wp) :: time
    integer :: first, last, stat
    first = len(begin_mark) + 1
    last = index(line, ' -->', back=.true.) - 1
    time = 0.0_wp
    stat = 1
    if (last >= first) read(line(first:last), *, iostat=stat) time
    if (stat /= 0) call fatal('xdmf_update_series: bad dump marker in ' // trim(source))
  end function marked_time

  !> One line of any length from a formatted sequential unit (`stat` as `iostat`).
  subroutine read_line(unit, line, stat)
    integer, intent(in) :: unit                           !< open input unit
    character(len=:), allocatable, intent(out) :: line    !< line without newline
    integer, intent(out) :: stat                          !< 0, or iostat end/error
    character(len=256) :: chunk
    integer :: nread
    line = ''
    do
      read(unit, '(a)', advance='no', iostat=stat, size=nread) chunk
      line = line // chunk(1:nread)
      if (is_iostat_eor(stat)) then
        stat = 0
        return
      end if
      if (stat /= 0) return
    end do
  end subroutine read_line

  !> Write one line, stopping with the file name on failure.
  subroutine put(unit, path, text)
    integer, intent(in) :: unit           !< open output unit
    character(len=*), intent(in) :: path  !< file (for messages)
    character(len=*), intent(in) :: text  !< line
    integer :: stat
    character(len=msg_len) :: msg
    write(unit, '(a)', iostat=stat, iomsg=msg) text
    if (stat /= 0) call write_failed(path, 'write', msg)
  end subroutine put

  !> A failed write of the XDMF file `path`: the run ends with one line and exit status 3 and
  !! the file is removed (`io_write_failed`); a temporary `.tmp` file is named by its final name.
  subroutine write_failed(path, operation, msg)
    character(len=*), intent(in) :: path       !< file being written
    character(len=*), intent(in) :: operation  !< open, write or close
    character(len=*), intent(in) :: msg        !< the run-time library's message
    character(len=:), allocatable :: final
    final = trim(path)
    if (len(final) > 4) then
      if (final(len(final) - 3:) == '.tmp') final = final(1:len(final) - 4)
    end if
    call io_write_failed(trim(path), final, 'XDMF ' // operation, 0, message=msg)
  end subroutine write_failed
end module io_xdmf
