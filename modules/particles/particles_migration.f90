!> Particle migration after the position update: every particle goes to the rank whose block
!! owns the cell containing it; particles outside the domain along a non-periodic active
!! dimension are removed and counted; in a periodic dimension positions are wrapped.
!!
!! Owners come from tables built once (`migration_init`): the block coordinate of every global
!! cell index per dimension and the rank of every block (MPI_Cart_rank). Particles travel packed
!! as `particle_reals(p)` reals (the 64-bit id bit-copied; the model-specific state only when the
!! store carries it: `n_common` + 1 for Cam-Clay's p_c, + `n_cyclic_state` for the sand's cyclic
!! state, + 1 for its gap, + `n_affine` for APIC) through one MPI_Alltoall of counts and one
!! MPI_Alltoallv; received particles are appended in source-rank order. The send buffers grow amortised and are kept between calls.
module particles_migration
  use mpmice_kinds, only: wp, i8
  use grid_layout, only: grid_t
  use parallel_domain, only: domain_t, domain_block_range
  use parallel_comm, only: alltoall_counts, alltoallv_real, cart_rank
  use particles_store, only: particles_t, particles_reserve, particles_compact, n_cyclic_state, &
    n_affine
  implicit none
  private

  public :: migration_t, migration_init, migrate_particles, keep_inside_walls

  integer, parameter :: n_common = 34                 !< reals of every packed particle

  !> Ownership tables and buffers of the migration.
  type :: migration_t
    integer, allocatable :: coord_of_cell(:, :)   !< (max ncells, 3) block coordinate of a cell
    integer, allocatable :: rank_of(:, :, :)      !< (0:dims-1, ...) rank of a block
    integer, allocatable :: dest(:)               !< destination rank per particle (-1: leaves)
    real(wp), allocatable :: sendbuf(:)           !< (reals * n) packed outgoing particles
    real(wp), allocatable :: recvbuf(:)           !< (reals * n) packed incoming particles
    integer, allocatable :: scount(:), rcount(:), sdispl(:), rdispl(:)  !< per rank (reals)
    integer, allocatable :: slot(:)               !< (0:nranks-1) work: next send slot per rank
    logical, allocatable :: keep(:)               !< work: the particle stays (grown with dest)
  end type migration_t

contains

  !> Build the ownership tables of the decomposition.
  subroutine migration_init(mig, dom, grid)
    type(migration_t), intent(inout) :: mig  !< migration state
    type(domain_t), intent(in) :: dom        !< decomposition
    type(grid_t), intent(in) :: grid         !< block geometry
    integer :: d, c, lo, hi, a, b, e, coords(3)
    allocate(mig%coord_of_cell(maxval(grid%ncells), 3), source=0)
    do d = 1, 3
      do c = 0, dom%dims(d) - 1
        call domain_block_range(dom, d, c, lo, hi)
        mig%coord_of_cell(lo:hi, d) = c
      end do
    end do
    allocate(mig%rank_of(0:dom%dims(1) - 1, 0:dom%dims(2) - 1, 0:dom%dims(3) - 1))
    do e = 0, dom%dims(3) - 1
      do b = 0, dom%dims(2) - 1
        do a = 0, dom%dims(1) - 1
          ! the Cartesian communicator spans the active dimensions only (parallel_domain)
          coords = [a, b, e]
          if (count(dom%active) == 0) then
            mig%rank_of(a, b, e) = cart_rank(dom%comm, [0])
          else
            mig%rank_of(a, b, e) = cart_rank(dom%comm, pack(coords, dom%active))
          end if
        end do
      end do
    end do
    allocate(mig%scount(0:dom%nranks - 1), mig%rcount(0:dom%nranks - 1), &
      mig%sdispl(0:dom%nranks - 1), mig%rdispl(0:dom%nranks - 1), mig%slot(0:dom%nranks - 1))
    allocate(mig%dest(0), mig%keep(0), mig%sendbuf(0), mig%recvbuf(0))
  end subroutine migration_init

  !> Reals per packed particle of store `p`: the common fields and the model-specific state
  !! the store carries.
  pure integer function particle_reals(p) result(nf)
    type(particles_t), intent(in) :: p  !< store
    nf = n_common
    if (p%has_hardening) nf = nf + 1
    if (p%has_cyclic) nf = nf + n_cyclic_state
    if (p%has_gap) nf = nf + 1
    if (p%has_affine) nf = nf + n_affine
  end function particle_reals

  !> Put back on the face plane every particle of `p` whose centre passed a closed face of the
  !! domain (`closed(face)`, faces in the `&boundary` order x-, x+, y-, y+, z-, z+; only active,
  !! non-periodic dimensions), so that `migrate_particles` does not remove it as having left the
  !! domain: a solid's wall (`solid = 'fixed'` or `'roller'`) stops its nodes' normal motion, but
  !! the particle of a GIMP domain reaching past the wall still takes the velocity of the inner
  !! nodes and can drift through. On the high face the particle goes just inside (1e-9 of a cell),
  !! so that it stays in the last cell, and its velocity loses the component out of the domain
  !! (the wall stops the normal motion, as its nodes do). `moved` counts the particles put back.
  subroutine keep_inside_walls(p, grid, closed, moved)
    type(particles_t), intent(inout) :: p    !< particles
    type(grid_t), intent(in) :: grid         !< block geometry
    logical, intent(in) :: closed(6)         !< the faces the particles may not pass
    integer, intent(out) :: moved            !< particles put back
    integer :: ip, d
    real(wp) :: lo(3), hi(3), x
    logical :: back
    moved = 0
    if (.not. any(closed)) return
    lo = grid%lower
    hi = grid%upper - 1.0e-9_wp * grid%dx
    do ip = 1, p%np
      back = .false.
      do d = 1, 3
        if (.not. grid%active(d) .or. grid%periodic(d)) cycle
        x = p%x(d, ip)
        if (closed(2 * d - 1) .and. x < lo(d)) then
          p%x(d, ip) = lo(d)
          p%v(d, ip) = max(p%v(d, ip), 0.0_wp)
        end if
        if (closed(2 * d) .and. x > hi(d)) then
          p%x(d, ip) = hi(d)
          p%v(d, ip) = min(p%v(d, ip), 0.0_wp)
        end if
        back = back .or. p%x(d, ip) /= x
      end do
      if (back) moved = moved + 1
    end do
  end subroutine keep_inside_walls

  !> Send every particle of `p` to its owner; `removed` = particles of this rank that left the
  !! domain (local count). Collective.
  subroutine migrate_particles(mig, p, dom, grid, removed)
    type(migration_t), intent(inout) :: mig  !< migration state
    type(particles_t), intent(inout) :: p    !< particles
    type(domain_t), intent(in) :: dom        !< decomposition
    type(grid_t), intent(in) :: grid         !< block geometry
    integer, intent(out) :: removed          !< particles removed (left the domain)
    integer :: ip, d, ci, coords(3), r, nsend, nrecv, n0, i, nf
    real(wp) :: span

    ! the work arrays grow (at least doubling) with the particle count, rarely
    if (size(mig%dest) < p%np) then
      n0 = max(p%np, 2 * size(mig%dest))
      deallocate(mig%dest, mig%keep)
      allocate(mig%dest(n0), mig%keep(n0))
    end if
    removed = 0
    mig%scount(:) = 0
    do ip = 1, p%np
      coords = 0
      mig%dest(ip) = dom%rank
      do d = 1, 3
        if (.not. grid%active(d)) cycle
        if (grid%periodic(d)) then
          span = grid%upper(d) - grid%lower(d)
          p%x(d, ip) = grid%lower(d) + modulo(p%x(d, ip) - grid%lower(d), span)
        end if
        ci = floor((p%x(d, ip) - grid%lower(d)) / grid%dx(d)) + 1
        if (grid%periodic(d)) ci = min(max(ci, 1), grid%ncells(d))
        if (ci < 1 .or. ci > grid%ncells(d)) then
          mig%dest(ip) = -1
          exit
        end if
        coords(d) = mig%coord_of_cell(ci, d)
      end do
      if (mig%dest(ip) < 0) then
        removed = removed + 1
        cycle
      end if
      mig%dest(ip) = mig%rank_of(coords(1), coords(2), coords(3))
      if (mig%dest(ip) /= dom%rank) mig%scount(mig%dest(ip)) = mig%scount(mig%dest(ip)) + 1
    end do

    nf = particle_reals(p)
    if (dom%nranks > 1) then
      nsend = sum(mig%scount)
      call reserve_reals(mig%sendbuf, nsend * nf)
      associate (slot => mig%slot)
        slot(:) = exclusive_offsets(mig%scount, 1)
        mig%sdispl(:) = slot * nf
        do ip = 1, p%np
          r = mig%dest(ip)
          if (r < 0 .or. r == dom%rank) cycle
          slot(r) = slot(r) + 1
          call pack_particle(p, ip, mig%sendbuf((slot(r) - 1) * nf + 1:slot(r) * nf))
        end do
      end associate
      call alltoall_counts(dom%comm, mig%scount, mig%rcount)
      nrecv = sum(mig%rcount)
      call reserve_reals(mig%recvbuf, nrecv * nf)
      mig%rdispl(:) = exclusive_offsets(mig%rcount, nf)
      call alltoallv_real(dom%comm, mig%sendbuf, mig%scount * nf, mig%sdispl, mig%recvbuf, &
        mig%rcount * nf, mig%rdispl)
    else
      nrecv = 0
    end if

    if (removed > 0 .or. any(mig%dest(1:p%np) /= dom%rank)) then
      mig%keep(1:p%np) = mig%dest(1:p%np) == dom%rank
      call particles_compact(p, mig%keep(1:p%np))
    end if
    if (nrecv > 0) then
      n0 = p%np
      call particles_reserve(p, n0 + nrecv)
      do i = 1, nrecv
        call unpack_particle(mig%recvbuf((i - 1) * nf + 1:i * nf), p, n0 + i)
      end do
      p%np = n0 + nrecv
    end if
  end subroutine migrate_particles

  !> Grow the message buffer `buf` to at least `n` reals (at least doubling, so that a growing
  !! exchange reallocates rarely; the contents are not kept).
  subroutine reserve_reals(buf, n)
    real(wp), allocatable, intent(inout) :: buf(:)  !< buffer
    integer, intent(in) :: n                        !< reals needed
    integer :: capacity
    if (size(buf) >= n) return
    capacity = max(n, 2 * size(buf))
    deallocate(buf)
    allocate(buf(capacity))
  end subroutine reserve_reals

  !> Offsets of consecutive blocks of `counts(r) * scale` entries, rank 0 first: the
  !! displacements of an all-to-all exchange.
  pure function exclusive_offsets(counts, scale) result(offsets)
    integer, intent(in) :: counts(0:)            !< (0:nranks-1) block sizes
    integer, intent(in) :: scale                 !< entries per count
    integer :: offsets(0:size(counts) - 1)
    integer :: r
    offsets(0) = 0
    do r = 1, size(counts) - 1
      offsets(r) = offsets(r - 1) + counts(r - 1) * scale
    end do
  end function exclusive_offsets

  !> Pack particle `ip` into `buf(particle_reals(p))`.
  pure subroutine pack_particle(p, ip, buf)
    type(particles_t), intent(in) :: p   !< particles
    integer, intent(in) :: ip            !< particle
    real(wp), intent(out) :: buf(:)      !< packed values
    integer :: k
    buf(1:3) = p%x(:, ip)
    buf(4:6) = p%v(:, ip)
    buf(7) = p%mass(ip)
    buf(8) = p%volume(ip)
    buf(9) = p%volume0(ip)
    buf(10:18) = p%f(:, ip)
    buf(19:24) = p%stress(:, ip)
    buf(25:30) = p%stress_unrot(:, ip)
    buf(31) = p%plastic_strain(ip)
    buf(32) = p%temperature(ip)
    buf(33) = p%pore_pressure(ip)
    buf(34) = transfer(p%id(ip), 1.0_wp)
    k = n_common
    if (p%has_hardening) then
      buf(k + 1) = p%hardening(ip)
      k = k + 1
    end if
    if (p%has_cyclic) then
      buf(k + 1:k + n_cyclic_state) = p%cyclic(:, ip)
      k = k + n_cyclic_state
    end if
    if (p%has_gap) then
      buf(k + 1) = p%gap(ip)
      k = k + 1
    end if
    if (p%has_affine) buf(k + 1:k + n_affine) = p%affine(:, ip)
  end subroutine pack_particle

  !> Unpack `buf(particle_reals(p))` into slot `ip` of `p` (capacity must suffice).
  pure subroutine unpack_particle(buf, p, ip)
    real(wp), intent(in) :: buf(:)        !< packed values
    type(particles_t), intent(inout) :: p !< particles
    integer, intent(in) :: ip             !< slot
    integer :: k
    p%x(:, ip) = buf(1:3)
    p%v(:, ip) = buf(4:6)
    p%mass(ip) = buf(7)
    p%volume(ip) = buf(8)
    p%volume0(ip) = buf(9)
    p%f(:, ip) = buf(10:18)
    p%stress(:, ip) = buf(19:24)
    p%stress_unrot(:, ip) = buf(25:30)
    p%plastic_strain(ip) = buf(31)
    p%temperature(ip) = buf(32)
    p%pore_pressure(ip) = buf(33)
    p%id(ip) = transfer(buf(34), 1_i8)
    k = n_common
    if (p%has_hardening) then
      p%hardening(ip) = buf(k + 1)
      k = k + 1
    end if
    if (p%has_cyclic) then
      p%cyclic(:, ip) = buf(k + 1:k + n_cyclic_state)
      k = k + n_cyclic_state
    end if
    if (p%has_gap) then
      p%gap(ip) = buf(k + 1)
      k = k + 1
    end if
    if (p%has_affine) p%affine(:, ip) = buf(k + 1:k + n_affine)
  end subroutine unpack_particle
end module particles_migration
