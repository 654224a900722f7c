!> Halo exchange of cell and node fields, and the reverse halo (sum into the owner) for
!! particle-to-grid scatters.
!!
!! Conventions are those of `grid_layout` (global 1-based indices, cell fields `lbc..ubc`, node
!! fields `lbn..ubn`). Dimensions are exchanged one after the other (x, y, z); each sweep carries
!! the ghost layers already filled by the previous sweeps, so edges and corners come out right with
!! face neighbours only. Every message is a nonblocking `MPI_Isend`/`MPI_Irecv` pair through the
!! contiguous buffers of a `halo_t`, allocated once by `halo_init`; messages carry a tag per
!! dimension and direction, so a periodic dimension with one block exchanges with itself.
!!
!! Locations outside the domain in a non-periodic dimension (wall ghosts, and every edge or corner
!! ghost that lies beyond a wall) are never read for sending nor written: they belong to the
!! boundary-condition code. See docs/parallel.md.
module parallel_halo
  use mpi_f08, only: MPI_Request, MPI_Isend, MPI_Irecv, MPI_Waitall, MPI_DOUBLE_PRECISION, &
    MPI_PROC_NULL, MPI_REQUEST_NULL, MPI_STATUSES_IGNORE
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use parallel_domain, only: domain_t, domain_min_block_cells
  use parallel_halo_pack, only: box_size, pack_box, unpack_box
  use grid_layout, only: grid_t
  implicit none
  private

  public :: halo_t, halo_init, halo_free
  public :: halo_exchange_cell, halo_exchange_cell_vec
  public :: halo_exchange_node, halo_exchange_node_vec
  public :: halo_reverse_node, halo_reverse_node_vec, halo_reverse_cell_vec

  !> Message buffers of the halo exchange of one block (allocated once, reused by every call).
  type :: halo_t
    integer :: max_components = 0            !< largest leading extent of rank-4 fields
    integer :: capacity = 0                  !< reals per buffer
    real(wp), allocatable :: send_buf(:, :)  !< (capacity, side): packed outgoing slabs
    real(wp), allocatable :: recv_buf(:, :)  !< (capacity, side): incoming slabs
    logical :: initialized = .false.         !< set by halo_init
  end type halo_t

  !> Fill the ghost cells of a cell field (rank 3, or rank 4 with a leading component index).
  interface halo_exchange_cell
    module procedure halo_exchange_cell_scalar, halo_exchange_cell_vec
  end interface halo_exchange_cell

  !> Fill every non-owned node of a node field from its owner.
  interface halo_exchange_node
    module procedure halo_exchange_node_scalar, halo_exchange_node_vec
  end interface halo_exchange_node

  !> Add every non-owned node value into its owner, then (by default) refresh the copies.
  interface halo_reverse_node
    module procedure halo_reverse_node_scalar, halo_reverse_node_vec
  end interface halo_reverse_node

  integer, parameter :: stage_cell = 1      !< plan of a cell exchange
  integer, parameter :: stage_node = 2      !< plan of a node exchange
  integer, parameter :: stage_reverse = 3   !< plan of a reverse node halo
  integer, parameter :: stage_reverse_cell = 4  !< plan of a reverse cell halo
  integer, parameter :: tag_base = 7100     !< first message tag used here

contains

  !> Allocate the message buffers for the fields of `grid`: any cell or node field with at most
  !! `max_components` components (default 1). Calls `halo_free` first.
  subroutine halo_init(halo, dom, grid, max_components)
    type(halo_t), intent(inout) :: halo             !< buffers to set up
    type(domain_t), intent(in) :: dom               !< decomposition
    type(grid_t), intent(in) :: grid                !< this block's index ranges
    integer, intent(in), optional :: max_components !< largest rank-4 leading extent
    integer :: d, e, points, largest, stat
    character(len=256) :: errmsg

    call halo_free(halo)
    if (.not. dom%initialized) call fatal('halo_init: the domain is not initialised')
    halo%max_components = 1
    if (present(max_components)) halo%max_components = max(1, max_components)
    largest = 1
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      points = grid%ng(d) + 1
      do e = 1, 3
        if (e /= d) points = points * (grid%ubn(e) - grid%lbn(e) + 1)
      end do
      largest = max(largest, points)
    end do
    halo%capacity = largest * halo%max_components
    allocate(halo%send_buf(halo%capacity, 2), stat=stat, errmsg=errmsg)
    if (stat /= 0) call fatal('halo_init: cannot allocate send buffers: ' // trim(errmsg))
    allocate(halo%recv_buf(halo%capacity, 2), stat=stat, errmsg=errmsg)
    if (stat /= 0) call fatal('halo_init: cannot allocate receive buffers: ' // trim(errmsg))
    halo%send_buf(:, :) = 0.0_wp
    halo%recv_buf(:, :) = 0.0_wp
    halo%initialized = .true.
  end subroutine halo_init

  !> Release the buffers.
  subroutine halo_free(halo)
    type(halo_t), intent(inout) :: halo  !< buffers to release
    if (allocated(halo%send_buf)) deallocate(halo%send_buf)
    if (allocated(halo%recv_buf)) deallocate(halo%recv_buf)
    halo%max_components = 0
    halo%capacity = 0
    halo%initialized = .false.
  end subroutine halo_free

  !> Fill the ghost cells of `field` (allocated `grid%lbc:grid%ubc`) up to `width` layers
  !! (default and maximum: the ghost width), edges and corners included. Collective.
  subroutine halo_exchange_cell_scalar(halo, dom, grid, field, width)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    integer, intent(in), optional :: width      !< ghost layers to fill (<= ng)
    call check_bounds(halo, shape(field), grid%ubc - grid%lbc + 1, 1, 'halo_exchange_cell')
    call sweeps(halo, dom, grid, 1, grid%lbc, grid%ubc, field, stage_cell, &
      cell_width(grid, width))
  end subroutine halo_exchange_cell_scalar

  !> Rank-4 variant of `halo_exchange_cell` for fields `(component, i, j, k)`.
  subroutine halo_exchange_cell_vec(halo, dom, grid, field, width)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    integer, intent(in), optional :: width      !< ghost layers to fill (<= ng)
    call check_bounds(halo, point_extents(field), grid%ubc - grid%lbc + 1, size(field, 1), &
      'halo_exchange_cell')
    call sweeps(halo, dom, grid, size(field, 1), grid%lbc, grid%ubc, field, stage_cell, &
      cell_width(grid, width))
  end subroutine halo_exchange_cell_vec

  !> Fill every non-owned node of `field` (allocated `grid%lbn:grid%ubn`) from its owner: the ghost
  !! layers, the node `hi+1` of inner blocks and periodic images. Collective.
  subroutine halo_exchange_node_scalar(halo, dom, grid, field)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node field
    call check_bounds(halo, shape(field), grid%ubn - grid%lbn + 1, 1, 'halo_exchange_node')
    call sweeps(halo, dom, grid, 1, grid%lbn, grid%ubn, field, stage_node, grid%ng)
  end subroutine halo_exchange_node_scalar

  !> Rank-4 variant of `halo_exchange_node` for fields `(component, i, j, k)`.
  subroutine halo_exchange_node_vec(halo, dom, grid, field)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node field
    call check_bounds(halo, point_extents(field), grid%ubn - grid%lbn + 1, size(field, 1), &
      'halo_exchange_node')
    call sweeps(halo, dom, grid, size(field, 1), grid%lbn, grid%ubn, field, stage_node, grid%ng)
  end subroutine halo_exchange_node_vec

  !> Reverse halo of a node field: every value held at a non-owned in-domain node location is added
  !! into the owner's node and the location is zeroed; then, unless `refresh` is false, the copies
  !! are refreshed from the owners (a `halo_exchange_node`). Collective.
  subroutine halo_reverse_node_scalar(halo, dom, grid, field, refresh)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node field
    logical, intent(in), optional :: refresh    !< refresh the copies afterwards (default true)
    call check_bounds(halo, shape(field), grid%ubn - grid%lbn + 1, 1, 'halo_reverse_node')
    call sweeps(halo, dom, grid, 1, grid%lbn, grid%ubn, field, stage_reverse, grid%ng)
    if (want_refresh(refresh)) call halo_exchange_node_scalar(halo, dom, grid, field)
  end subroutine halo_reverse_node_scalar

  !> Rank-4 variant of `halo_reverse_node` for fields `(component, i, j, k)`.
  subroutine halo_reverse_node_vec(halo, dom, grid, field, refresh)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node field
    logical, intent(in), optional :: refresh    !< refresh the copies afterwards (default true)
    call check_bounds(halo, point_extents(field), grid%ubn - grid%lbn + 1, size(field, 1), &
      'halo_reverse_node')
    call sweeps(halo, dom, grid, size(field, 1), grid%lbn, grid%ubn, field, stage_reverse, &
      grid%ng)
    if (want_refresh(refresh)) call halo_exchange_node_vec(halo, dom, grid, field)
  end subroutine halo_reverse_node_vec

  !> Reverse halo of a cell field `(component, i, j, k)` over `width` ghost layers (default 1):
  !! every value scattered into an in-domain ghost cell is added into the owner's cell and the
  !! ghost is zeroed; then the ghost copies are refreshed from the owners. Used for particle
  !! deposits that reach into the neighbouring block (particle-domain overlaps); then all ghost
  !! layers are refreshed from the owners. Collective.
  subroutine halo_reverse_cell_vec(halo, dom, grid, field, width)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    real(wp), intent(inout) :: field(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    integer, intent(in), optional :: width      !< ghost layers to sum (<= ng, default 1)
    integer :: w(3)
    call check_bounds(halo, point_extents(field), grid%ubc - grid%lbc + 1, size(field, 1), &
      'halo_reverse_cell')
    w = cell_width(grid, 1)
    if (present(width)) w = cell_width(grid, width)
    call sweeps(halo, dom, grid, size(field, 1), grid%lbc, grid%ubc, field, stage_reverse_cell, w)
    ! refresh every ghost layer: the summed values feed fields used across the full width
    call halo_exchange_cell_vec(halo, dom, grid, field)
  end subroutine halo_reverse_cell_vec

  !> The sweeps of one exchange of `stage` over `w` layers, x, y, z in turn (a node stage
  !! repeats a sweep `node_passes` times). `field` is `(component, i, j, k)` with `ncomp`
  !! components; a scalar field comes in by sequence association with `ncomp` = 1.
  subroutine sweeps(halo, dom, grid, ncomp, lb, ub, field, stage, w)
    type(halo_t), intent(inout) :: halo         !< message buffers
    type(domain_t), intent(in) :: dom           !< decomposition
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    integer, intent(in) :: ncomp                !< components per point
    integer, intent(in) :: lb(3)                !< lower bounds of the points
    integer, intent(in) :: ub(3)                !< upper bounds of the points
    real(wp), intent(inout) :: field(ncomp, lb(1):ub(1), lb(2):ub(2), lb(3):ub(3))  !< field
    integer, intent(in) :: stage                !< stage_cell, stage_node, stage_reverse, ...
    integer, intent(in) :: w(3)                 !< layers per dimension
    integer :: d, pass, npasses, sbox(2, 3, 2), rbox(2, 3, 2)
    logical :: reverse
    reverse = stage == stage_reverse .or. stage == stage_reverse_cell
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      call plan_sweep(grid, d, stage, w, sbox, rbox)
      npasses = 1
      if (stage == stage_node .or. stage == stage_reverse) npasses = node_passes(dom, d)
      do pass = 1, npasses
        call sweep(halo, dom, d, ncomp, lb, ub, field, sbox, rbox, reverse)
      end do
    end do
  end subroutine sweeps

  !> Extents of the points `(i, j, k)` of a field `(component, i, j, k)`.
  pure function point_extents(field) result(ext)
    real(wp), intent(in) :: field(:, :, :, :)  !< field
    integer :: ext(3)
    ext = [size(field, 2), size(field, 3), size(field, 4)]
  end function point_extents

  ! ------------------------------------------------------------------ planning

  !> Ghost layers per dimension of a cell exchange: `width` clipped to the ghost width.
  pure function cell_width(grid, width) result(w)
    type(grid_t), intent(in) :: grid            !< this block's index ranges
    integer, intent(in), optional :: width      !< requested layers
    integer :: w(3)
    w = grid%ng
    if (present(width)) w = max(0, min(width, grid%ng))
  end function cell_width

  !> Sweeps needed along `d` for nodes: two when a block may own fewer than ng+1 nodes there, so
  !! that the outermost node copy (owned two blocks away) arrives through the neighbour's copy.
  pure function node_passes(dom, d) result(n)
    type(domain_t), intent(in) :: dom  !< decomposition
    integer, intent(in) :: d           !< dimension
    integer :: n
    n = 1
    if (domain_min_block_cells(dom, d) < dom%ng(d) + 1) n = 2
  end function node_passes

  !> Whether the reverse halo refreshes the copies (default true).
  pure logical function want_refresh(refresh)
    logical, intent(in), optional :: refresh  !< caller's choice
    want_refresh = .true.
    if (present(refresh)) want_refresh = refresh
  end function want_refresh

  !> Boxes of the sweep along `d`: `sbox(:, :, s)` is sent to the neighbour on side s (1 low,
  !! 2 high), `rbox(:, :, s)` receives from it. Along the other dimensions a box spans, in already
  !! swept dimensions, the part filled so far (cells: owned plus `w`, nodes: the whole allocation,
  !! reverse: owned nodes only) and, in the others, the owned range (reverse: the whole allocation);
  !! both clipped to the domain in non-periodic dimensions. Neighbours along `d` share these
  !! ranges, so the two ends of a message agree on its size and order.
  pure subroutine plan_sweep(grid, d, stage, w, sbox, rbox)
    type(grid_t), intent(in) :: grid          !< this block's index ranges
    integer, intent(in) :: d                  !< dimension of the sweep
    integer, intent(in) :: stage              !< stage_cell, stage_node or stage_reverse
    integer, intent(in) :: w(3)               !< ghost layers per dimension
    integer, intent(out) :: sbox(2, 3, 2)     !< boxes to send (first/last, dim, side)
    integer, intent(out) :: rbox(2, 3, 2)     !< boxes to receive (first/last, dim, side)
    integer :: e, span(2, 3), lo, hi, top

    do e = 1, 3
      top = grid%ncells(e)
      if (stage /= stage_cell .and. stage /= stage_reverse_cell) top = top + 1
      if (e == d .or. .not. grid%active(e)) then
        span(:, e) = [grid%lo(e), grid%hi(e)]
      else if (stage == stage_reverse_cell) then
        if (e > d) then
          span(:, e) = [grid%lbc(e), grid%ubc(e)]
        else
          span(:, e) = [grid%lo(e), grid%hi(e)]
        end if
      else if (stage == stage_cell) then
        if (e < d) then
          span(:, e) = [grid%lo(e) - w(e), grid%hi(e) + w(e)]
        else
          span(:, e) = [grid%lo(e), grid%hi(e)]
        end if
      else if ((stage == stage_node .and. e < d) .or. (stage == stage_reverse .and. e > d)) then
        span(:, e) = [grid%lbn(e), grid%ubn(e)]
      else
        span(:, e) = [grid%nlo(e), grid%nhi(e)]
      end if
      if (e /= d .and. grid%active(e) .and. .not. grid%periodic(e)) then
        span(1, e) = max(span(1, e), 1)
        span(2, e) = min(span(2, e), top)
      end if
    end do
    do e = 1, 2
      sbox(:, :, e) = span
      rbox(:, :, e) = span
    end do

    lo = grid%lo(d)
    hi = grid%hi(d)
    select case (stage)
    case (stage_cell)
      sbox(:, d, 1) = [lo, lo + w(d) - 1]
      sbox(:, d, 2) = [hi - w(d) + 1, hi]
      rbox(:, d, 1) = [lo - w(d), lo - 1]
      rbox(:, d, 2) = [hi + 1, hi + w(d)]
    case (stage_node)
      sbox(:, d, 1) = [lo, lo + w(d)]
      sbox(:, d, 2) = [hi - w(d) + 1, hi]
      rbox(:, d, 1) = [lo - w(d), lo - 1]
      rbox(:, d, 2) = [hi + 1, hi + 1 + w(d)]
    case (stage_reverse_cell)
      sbox(:, d, 1) = [lo - w(d), lo - 1]
      sbox(:, d, 2) = [hi + 1, hi + w(d)]
      rbox(:, d, 1) = [lo, lo + w(d) - 1]
      rbox(:, d, 2) = [hi - w(d) + 1, hi]
    case default
      sbox(:, d, 1) = [lo - w(d), lo - 1]
      sbox(:, d, 2) = [hi + 1, hi + 1 + w(d)]
      rbox(:, d, 1) = [lo, lo + w(d)]
      rbox(:, d, 2) = [hi - w(d) + 1, hi]
    end select
  end subroutine plan_sweep

  !> Abort unless the field matches the grid and the buffers are large enough.
  subroutine check_bounds(halo, extent, expected, ncomp, caller)
    type(halo_t), intent(in) :: halo     !< message buffers
    integer, intent(in) :: extent(3)     !< the field's spatial extents
    integer, intent(in) :: expected(3)   !< the extents the grid prescribes
    integer, intent(in) :: ncomp         !< components of the field
    character(len=*), intent(in) :: caller  !< routine name for the message
    if (.not. halo%initialized) call fatal(caller // ': halo_init was not called')
    if (any(extent /= expected)) call fatal(caller // ': field extents do not match the grid')
    if (ncomp > halo%max_components) then
      call fatal(caller // ': more components than halo_init was given')
    end if
  end subroutine check_bounds

  ! ------------------------------------------------------------------ messages

  !> Message tag of a message travelling along `d` toward side `s` of its sender.
  pure integer function message_tag(d, s)
    integer, intent(in) :: d  !< dimension
    integer, intent(in) :: s  !< 1 toward the low neighbour, 2 toward the high one
    message_tag = tag_base + 2 * d + s
  end function message_tag

  !> Post the receives of a sweep along `d` (`count(s)` reals from side s) into `req(1:2)`.
  subroutine post_receives(halo, dom, d, count, req)
    type(halo_t), intent(inout), asynchronous :: halo  !< message buffers
    type(domain_t), intent(in) :: dom                  !< decomposition
    integer, intent(in) :: d                           !< dimension
    integer, intent(in) :: count(2)                    !< reals expected per side
    type(MPI_Request), intent(inout) :: req(4)         !< requests (1:2 receives, 3:4 sends)
    integer :: s
    req(:) = MPI_REQUEST_NULL
    do s = 1, 2
      if (dom%neighbour(s, d) == MPI_PROC_NULL .or. count(s) == 0) cycle
      call MPI_Irecv(halo%recv_buf(1, s), count(s), MPI_DOUBLE_PRECISION, dom%neighbour(s, d), &
        message_tag(d, 3 - s), dom%comm, req(s))
    end do
  end subroutine post_receives

  !> Start sending `count` packed reals to the neighbour on side `s` along `d`.
  subroutine start_send(halo, dom, d, s, count, req)
    type(halo_t), intent(inout), asynchronous :: halo  !< message buffers
    type(domain_t), intent(in) :: dom                  !< decomposition
    integer, intent(in) :: d                           !< dimension
    integer, intent(in) :: s                           !< side (1 low, 2 high)
    integer, intent(in) :: count                       !< reals to send
    type(MPI_Request), intent(inout) :: req(4)         !< requests (1:2 receives, 3:4 sends)
    call MPI_Isend(halo%send_buf(1, s), count, MPI_DOUBLE_PRECISION, dom%neighbour(s, d), &
      message_tag(d, s), dom%comm, req(2 + s))
  end subroutine start_send

  !> One sweep along `d`: pack, exchange, unpack (copy, or add when `reverse`, in which case the
  !! sent boxes are zeroed). `field` is `(component, i, j, k)` with `ncomp` components; a
  !! scalar field `(i, j, k)` comes in by sequence association with `ncomp` = 1.
  subroutine sweep(halo, dom, d, ncomp, lb, ub, field, sbox, rbox, reverse)
    type(halo_t), intent(inout), asynchronous :: halo  !< message buffers
    type(domain_t), intent(in) :: dom                  !< decomposition
    integer, intent(in) :: d                           !< dimension
    integer, intent(in) :: ncomp                       !< components per point
    integer, intent(in) :: lb(3)                       !< lower bounds of the points
    integer, intent(in) :: ub(3)                       !< upper bounds of the points
    real(wp), intent(inout) :: field(ncomp, lb(1):ub(1), lb(2):ub(2), lb(3):ub(3))  !< field
    integer, intent(in) :: sbox(2, 3, 2)               !< boxes to send
    integer, intent(in) :: rbox(2, 3, 2)               !< boxes to receive
    logical, intent(in) :: reverse                     !< reverse halo
    type(MPI_Request) :: req(4)
    integer :: s, nsend(2), nrecv(2)
    do s = 1, 2
      nsend(s) = ncomp * box_size(sbox(:, :, s))
      nrecv(s) = ncomp * box_size(rbox(:, :, s))
    end do
    call post_receives(halo, dom, d, nrecv, req)
    do s = 1, 2
      if (dom%neighbour(s, d) == MPI_PROC_NULL .or. nsend(s) == 0) cycle
      call pack_box(field, lb, sbox(:, :, s), halo%send_buf(:, s), reverse)
      call start_send(halo, dom, d, s, nsend(s), req)
    end do
    call MPI_Waitall(4, req, MPI_STATUSES_IGNORE)
    do s = 1, 2
      if (dom%neighbour(s, d) == MPI_PROC_NULL .or. nrecv(s) == 0) cycle
      call unpack_box(field, lb, rbox(:, :, s), halo%recv_buf(:, s), reverse)
    end do
  end subroutine sweep
end module parallel_halo
