!> Cartesian MPI decomposition of a uniform grid over its active dimensions.
!!
!! One block per rank. `MPI_Dims_create` splits the ranks over the active dimensions only; an
!! inactive dimension (one cell) always has one block and no ghost layers. Along a dimension the
!! cells are split evenly (`block_range`) unless the caller gives the cells of each block
!! (`&grid block_cells_x/y/z`: uneven blocks that balance a scene whose work is not uniform).
!! Library code receives the communicator through `domain_t` and never touches `MPI_COMM_WORLD`.
module parallel_domain
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_Dims_create, MPI_Cart_create, &
    MPI_Cart_coords, MPI_Cart_shift, MPI_Comm_free, MPI_PROC_NULL, MPI_COMM_NULL, operator(/=)
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  implicit none
  private

  public :: domain_t, domain_init, domain_free, block_range, choose_dims, blocks_given, &
    domain_block_range, domain_min_block_cells, grid_init

  !> A rank's place in the Cartesian decomposition.
  type :: domain_t
    type(MPI_Comm) :: comm                  !< Cartesian communicator (owned, freed by domain_free)
    integer :: rank = 0                     !< rank in `comm`
    integer :: nranks = 1                   !< size of `comm`
    integer :: ndim = 0                     !< number of active dimensions
    logical :: active(3) = .false.          !< dimension has more than one cell
    logical :: periodic(3) = .false.        !< periodic in this dimension
    integer :: dims(3) = 1                  !< blocks per dimension
    integer :: coords(3) = 0                !< this block's 0-based coordinates
    integer :: neighbour(2, 3) = -1         !< (low/high, dim) neighbour ranks, MPI_PROC_NULL at walls
    integer :: ncells(3) = 1                !< global cells per dimension
    integer :: lo(3) = 1                    !< first owned cell (global index, 1-based)
    integer :: hi(3) = 1                    !< last owned cell (global index)
    integer :: ng(3) = 0                    !< ghost width per dimension (0 where inactive)
    !> (0:max dims, d): first cell of each block along d; entry dims(d) is ncells(d) + 1
    integer, allocatable :: first_cell(:, :)
    logical :: initialized = .false.        !< set by domain_init
  end type domain_t

contains

  !> Build the Cartesian decomposition of `ncells` cells over the ranks of `parent`.
  !! `dims_request` (optional) fixes the number of blocks per dimension (0 = let MPI choose).
  !! `block_cells` (optional, (:, 3)): the cells of each block along a dimension, its leading
  !! positive entries (`blocks_given` of them fix the blocks along that dimension; all zero: an
  !! even split). Aborts if a block would hold fewer cells than the ghost width or the given
  !! blocks do not tile the dimension (callers validate before).
  subroutine domain_init(dom, parent, ncells, periodic, ghost_width, dims_request, block_cells)
    type(domain_t), intent(inout) :: dom           !< decomposition to build
    type(MPI_Comm), intent(in) :: parent           !< communicator to decompose (e.g. a dup of world)
    integer, intent(in) :: ncells(3)               !< global cells per dimension
    logical, intent(in) :: periodic(3)             !< periodic dimensions
    integer, intent(in) :: ghost_width             !< ghost layers in active dimensions
    integer, intent(in), optional :: dims_request(3) !< blocks per dimension (0 = free)
    integer, intent(in), optional :: block_cells(:, :) !< cells per block along each dimension
    integer :: nranks, d, dims_active(3), nact, map(3), request(3), given(3), c, last
    logical :: periods(3)

    call domain_free(dom)
    call MPI_Comm_size(parent, nranks)
    dom%ncells = ncells
    dom%active = ncells > 1
    dom%ndim = count(dom%active)
    dom%periodic = periodic .and. dom%active
    dom%ng = 0
    where (dom%active) dom%ng = ghost_width

    request = 0
    if (present(dims_request)) request = dims_request
    given = 0
    if (present(block_cells)) then
      do d = 1, 3
        given(d) = blocks_given(block_cells(:, d))
        if (given(d) > 0) request(d) = given(d)
      end do
    end if
    dom%dims = choose_dims(nranks, dom%active, request)
    nact = 0
    do d = 1, 3
      if (dom%active(d)) then
        nact = nact + 1
        map(nact) = d
        dims_active(nact) = dom%dims(d)
        periods(nact) = dom%periodic(d)
      end if
    end do
    if (nact == 0) then
      nact = 1
      map(1) = 1
      dims_active(1) = 1
      periods(1) = .false.
    end if

    call MPI_Cart_create(parent, nact, dims_active(1:nact), periods(1:nact), .false., dom%comm)
    call MPI_Comm_rank(dom%comm, dom%rank)
    call MPI_Comm_size(dom%comm, dom%nranks)
    call MPI_Cart_coords(dom%comm, dom%rank, nact, dims_active(1:nact))
    dom%coords = 0
    dom%neighbour = MPI_PROC_NULL
    do d = 1, nact
      dom%coords(map(d)) = dims_active(d)
      if (dom%active(map(d))) then
        call MPI_Cart_shift(dom%comm, d - 1, 1, dom%neighbour(1, map(d)), dom%neighbour(2, map(d)))
      end if
    end do

    if (allocated(dom%first_cell)) deallocate(dom%first_cell)
    allocate(dom%first_cell(0:maxval(dom%dims), 3), source=0)
    do d = 1, 3
      if (given(d) > 0) then
        if (given(d) /= dom%dims(d) .or. sum(block_cells(1:given(d), d)) /= ncells(d)) then
          call fatal('domain_init: the given blocks do not tile the dimension')
        end if
        dom%first_cell(0, d) = 1
        do c = 1, given(d)
          dom%first_cell(c, d) = dom%first_cell(c - 1, d) + block_cells(c, d)
        end do
      else
        do c = 0, dom%dims(d) - 1
          call block_range(ncells(d), dom%dims(d), c, dom%first_cell(c, d), last)
        end do
        dom%first_cell(dom%dims(d), d) = ncells(d) + 1
      end if
      call domain_block_range(dom, d, dom%coords(d), dom%lo(d), dom%hi(d))
      if (dom%active(d) .and. domain_min_block_cells(dom, d) < max(dom%ng(d), 1)) then
        call fatal('domain_init: a block has fewer cells than the ghost width')
      end if
    end do
    dom%initialized = .true.
  end subroutine domain_init

  !> Blocks per dimension for `nranks` ranks: `MPI_Dims_create` over the active dimensions only,
  !! honouring the non-zero entries of `dims_request`. Used by `domain_init` and by input validation.
  function choose_dims(nranks, active, dims_request) result(dims)
    integer, intent(in) :: nranks                    !< number of ranks
    logical, intent(in) :: active(3)                 !< active dimensions
    integer, intent(in), optional :: dims_request(3) !< requested blocks per dimension (0 = free)
    integer :: dims(3)
    integer :: d, nact, dims_active(3), map(3)
    nact = 0
    dims_active = 0
    do d = 1, 3
      if (active(d)) then
        nact = nact + 1
        map(nact) = d
        if (present(dims_request)) dims_active(nact) = dims_request(d)
      end if
    end do
    dims = 1
    if (nact == 0) then
      if (nranks /= 1) call fatal('a single-cell grid can only run on one rank')
      return
    end if
    call MPI_Dims_create(nranks, nact, dims_active(1:nact))
    do d = 1, nact
      dims(map(d)) = dims_active(d)
    end do
  end function choose_dims

  !> Cells `lo..hi` owned by block `coord` of `nblocks` along a dimension of `n` cells: the first
  !! `mod(n, nblocks)` blocks get one extra cell.
  pure subroutine block_range(n, nblocks, coord, lo, hi)
    integer, intent(in) :: n        !< cells along the dimension
    integer, intent(in) :: nblocks  !< blocks along the dimension
    integer, intent(in) :: coord    !< 0-based block coordinate
    integer, intent(out) :: lo      !< first owned cell
    integer, intent(out) :: hi      !< last owned cell
    integer :: base, extra
    base = n / nblocks
    extra = mod(n, nblocks)
    lo = coord * base + min(coord, extra) + 1
    hi = lo + base - 1
    if (coord < extra) hi = hi + 1
  end subroutine block_range

  !> Number of blocks given by a `block_cells` column: the index of its last non-zero entry
  !! (0: none given, an even split).
  pure integer function blocks_given(cells)
    integer, intent(in) :: cells(:)  !< cells per block, zero-padded
    integer :: c
    blocks_given = 0
    do c = size(cells), 1, -1
      if (cells(c) /= 0) then
        blocks_given = c
        return
      end if
    end do
  end function blocks_given

  !> Cells `lo..hi` owned by block `coord` (0-based) along dimension `d` of the decomposition.
  pure subroutine domain_block_range(dom, d, coord, lo, hi)
    type(domain_t), intent(in) :: dom  !< decomposition (initialised)
    integer, intent(in) :: d           !< dimension
    integer, intent(in) :: coord       !< 0-based block coordinate
    integer, intent(out) :: lo         !< first owned cell
    integer, intent(out) :: hi         !< last owned cell
    lo = dom%first_cell(coord, d)
    hi = dom%first_cell(coord + 1, d) - 1
  end subroutine domain_block_range

  !> Fewest cells of a block along dimension `d`.
  pure integer function domain_min_block_cells(dom, d)
    type(domain_t), intent(in) :: dom  !< decomposition (initialised)
    integer, intent(in) :: d           !< dimension
    integer :: n
    n = dom%dims(d)
    domain_min_block_cells = minval(dom%first_cell(1:n, d) - dom%first_cell(0:n - 1, d))
  end function domain_min_block_cells

  !> Release the Cartesian communicator.
  subroutine domain_free(dom)
    type(domain_t), intent(inout) :: dom  !< decomposition to release
    if (dom%initialized) then
      if (dom%comm /= MPI_COMM_NULL) call MPI_Comm_free(dom%comm)
    end if
    dom%initialized = .false.
  end subroutine domain_free

  !> Geometry and index ranges of this rank's block from the decomposition `dom`.
  subroutine grid_init(grid, dom, lower, upper)
    type(grid_t), intent(out) :: grid    !< block geometry to fill
    type(domain_t), intent(in) :: dom    !< decomposition (already initialised)
    real(wp), intent(in) :: lower(3)     !< low corner of the domain [m]
    real(wp), intent(in) :: upper(3)     !< high corner of the domain [m]
    integer :: d

    grid%ndim = dom%ndim
    grid%active = dom%active
    grid%periodic = dom%periodic
    grid%ncells = dom%ncells
    grid%lower = lower
    grid%upper = upper
    grid%dx = (upper - lower) / real(dom%ncells, wp)
    grid%cell_volume = grid%dx(1) * grid%dx(2) * grid%dx(3)
    grid%ng = dom%ng
    grid%lo = dom%lo
    grid%hi = dom%hi
    grid%lbc = dom%lo - dom%ng
    grid%ubc = dom%hi + dom%ng
    do d = 1, 3
      grid%at_lower(d) = dom%coords(d) == 0
      grid%at_upper(d) = dom%coords(d) == dom%dims(d) - 1
      if (grid%active(d)) then
        grid%nlo(d) = dom%lo(d)
        grid%nhi(d) = dom%hi(d)
        if (grid%at_upper(d) .and. .not. grid%periodic(d)) grid%nhi(d) = dom%hi(d) + 1
        grid%lbn(d) = dom%lo(d) - dom%ng(d)
        grid%ubn(d) = dom%hi(d) + 1 + dom%ng(d)
      else
        grid%nlo(d) = 1
        grid%nhi(d) = 1
        grid%lbn(d) = 1
        grid%ubn(d) = 1
      end if
    end do
  end subroutine grid_init
end module parallel_domain
