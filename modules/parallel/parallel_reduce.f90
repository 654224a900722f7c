!> Global reductions over the ranks of a decomposition.
!!
!! Floating-point sums are *reproducible*: `global_sum` (reals) and `global_sum_field` convert every
!! value to a fixed-point number with a common binary exponent (set by the global largest
!! magnitude) held in `ndigits` 64-bit integers of `digit_bits` bits each, add the integers (exact,
!! so independent of order, of the reduction tree and of the number of ranks) and convert the
!! total back once. The result depends only on the global set of values, to the bit: the same
!! cell data give the same `global_sum_field` on 1, 2 or 4 ranks and for any block shape.
!! Bits below `2**(e - ndigits*digit_bits)`, with `2**e` just above the largest magnitude, are
!! dropped (truncated toward zero per value): 168 bits below the largest value, far beneath double
!! precision. Non-finite input (NaN, Inf) falls back to an ordinary `MPI_Allreduce` sum, which
!! propagates it. Integer sums, maxima, minima and logical reductions are exact by nature.
module parallel_reduce
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf
  use mpi_f08, only: MPI_Allreduce, MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_INTEGER8, MPI_SUM, &
    MPI_MAX, MPI_MIN, MPI_Op
  use mpmice_kinds, only: wp, i8
  use parallel_comm, only: all_and, all_or
  use parallel_domain, only: domain_t
  use grid_layout, only: grid_t
  implicit none
  private

  public :: global_sum, global_sum_field, global_max, global_min, global_any, global_all

  !> Sum over all ranks: reproducible for reals (scalar or elementwise over an array), exact for
  !! default and 64-bit integers.
  interface global_sum
    module procedure global_sum_real, global_sum_real_array, global_sum_int, global_sum_i8
  end interface global_sum

  !> Maximum over all ranks (real or integer).
  interface global_max
    module procedure global_max_real, global_max_int
  end interface global_max

  !> Minimum over all ranks (real or integer).
  interface global_min
    module procedure global_min_real, global_min_int
  end interface global_min

  integer, parameter :: ndigits = 4       !< fixed-point digits below the top carry digit
  integer, parameter :: digit_bits = 42   !< bits per digit (leaves 21 bits of carry headroom)
  integer, parameter :: flush_every = 2**20 !< additions between carry normalisations
  integer, parameter :: max_shift = 1000    !< largest power-of-two scaling done by multiplication
  real(wp), parameter :: digit_radix = 2.0_wp**digit_bits  !< weight ratio of adjacent digits

contains

  ! ------------------------------------------------------------------ reproducible real sums

  !> Reproducible sum of one real over all ranks [unit of x].
  function global_sum_real(dom, x) result(total)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    real(wp), intent(in) :: x          !< this rank's contribution
    real(wp) :: total
    real(wp) :: values(1), totals(1)
    values(1) = x
    totals = global_sum_real_array(dom, values)
    total = totals(1)
  end function global_sum_real

  !> Reproducible elementwise sum of `x(:)` over all ranks (one reduction for all elements).
  function global_sum_real_array(dom, x) result(total)
    type(domain_t), intent(in) :: dom   !< decomposition (its communicator)
    real(wp), intent(in) :: x(:)        !< this rank's contributions
    real(wp) :: total(size(x))
    real(wp) :: local_max(size(x)), biggest(size(x))
    integer(i8) :: acc(0:ndigits, size(x))
    integer :: n
    do n = 1, size(x)
      local_max(n) = magnitude(x(n), 0.0_wp)
    end do
    call MPI_Allreduce(local_max, biggest, size(x), MPI_DOUBLE_PRECISION, MPI_MAX, dom%comm)
    acc(:, :) = 0_i8
    do n = 1, size(x)
      if (biggest(n) > 0.0_wp .and. ieee_is_finite(biggest(n))) then
        call digits_add(x(n), exponent(biggest(n)), acc(:, n))
        call digits_normalize(acc(:, n))
      end if
    end do
    call reduce_digits(dom, acc)
    do n = 1, size(x)
      if (.not. ieee_is_finite(biggest(n))) then
        call MPI_Allreduce(x(n), total(n), 1, MPI_DOUBLE_PRECISION, MPI_SUM, dom%comm)
      else if (biggest(n) > 0.0_wp) then
        total(n) = digits_value(acc(:, n), exponent(biggest(n)))
      else
        total(n) = 0.0_wp
      end if
    end do
  end function global_sum_real_array

  !> Reproducible sum of a cell field over the owned cells `grid%lo..grid%hi` of every rank
  !! [unit of field]; bitwise independent of the number of ranks and of the block shape.
  function global_sum_field(dom, grid, field) result(total)
    type(domain_t), intent(in) :: dom   !< decomposition (its communicator)
    type(grid_t), intent(in) :: grid    !< this block's index ranges
    real(wp), intent(in) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    real(wp) :: total
    real(wp) :: local_max, biggest, local
    integer(i8) :: acc(0:ndigits, 1)
    integer :: i, j, k, e
    local_max = 0.0_wp
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          local_max = magnitude(field(i, j, k), local_max)
        end do
      end do
    end do
    call MPI_Allreduce(local_max, biggest, 1, MPI_DOUBLE_PRECISION, MPI_MAX, dom%comm)
    if (.not. ieee_is_finite(biggest)) then
      local = 0.0_wp
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            local = local + field(i, j, k)
          end do
        end do
      end do
      call MPI_Allreduce(local, total, 1, MPI_DOUBLE_PRECISION, MPI_SUM, dom%comm)
      return
    end if
    total = 0.0_wp
    if (biggest <= 0.0_wp) return
    e = exponent(biggest)
    acc(:, :) = 0_i8
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        call digits_add_row(field(grid%lo(1):grid%hi(1), j, k), e, acc(:, 1))
      end do
    end do
    call digits_normalize(acc(:, 1))
    call reduce_digits(dom, acc)
    total = digits_value(acc(:, 1), e)
  end function global_sum_field

  !> Running maximum magnitude: `max(running, abs(x))`, or +Inf once a non-finite value is seen
  !! (so that the global maximum flags it on every rank without comparing NaNs).
  elemental function magnitude(x, running) result(m)
    real(wp), intent(in) :: x        !< next value
    real(wp), intent(in) :: running  !< maximum so far
    real(wp) :: m
    if (.not. ieee_is_finite(x)) then
      m = ieee_value(1.0_wp, ieee_positive_inf)
    else
      m = max(running, abs(x))
    end if
  end function magnitude

  !> Add `x` as fixed-point digits with weights `2**(e - digit_bits*m)`, m = 1..ndigits, truncated
  !! toward zero; requires `abs(x) < 2**e`.
  pure subroutine digits_add(x, e, acc)
    real(wp), intent(in) :: x                     !< value
    integer, intent(in) :: e                      !< common exponent
    integer(i8), intent(inout) :: acc(0:ndigits)  !< accumulated digits
    real(wp) :: rest
    integer(i8) :: digit
    integer :: m
    rest = scale(x, digit_bits - e)
    do m = 1, ndigits
      digit = int(rest, i8)
      acc(m) = acc(m) + digit
      rest = scale(rest - real(digit, wp), digit_bits)
    end do
  end subroutine digits_add

  !> Add every value of `x(:)` (all `abs(x) < 2**e`) to the digits, as `digits_add` would one by
  !! one, with the scaling as one multiplication and the carries normalised per chunk.
  pure subroutine digits_add_row(x, e, acc)
    real(wp), intent(in) :: x(:)                  !< values
    integer, intent(in) :: e                      !< common exponent
    integer(i8), intent(inout) :: acc(0:ndigits)  !< accumulated digits, normalised on return
    real(wp) :: factor, rest
    integer(i8) :: digit, chunk(ndigits)
    integer :: n, m, first, last
    if (abs(digit_bits - e) > max_shift) then
      do n = 1, size(x)
        call digits_add(x(n), e, acc)
        if (modulo(n, flush_every) == 0) call digits_normalize(acc)
      end do
      call digits_normalize(acc)
      return
    end if
    factor = scale(1.0_wp, digit_bits - e)
    do first = 1, size(x), flush_every
      last = min(first + flush_every - 1, size(x))
      chunk(:) = 0_i8
      do n = first, last
        rest = x(n) * factor
        do m = 1, ndigits
          digit = int(rest, i8)
          chunk(m) = chunk(m) + digit
          rest = (rest - real(digit, wp)) * digit_radix
        end do
      end do
      acc(1:ndigits) = acc(1:ndigits) + chunk(:)
      call digits_normalize(acc)
    end do
  end subroutine digits_add_row

  !> Carry so that digits 1..ndigits lie in `[0, 2**digit_bits)`; digit 0 takes the carries and the
  !! sign.
  pure subroutine digits_normalize(acc)
    integer(i8), intent(inout) :: acc(0:ndigits)  !< digits
    integer(i8) :: carry
    integer :: m
    do m = ndigits, 1, -1
      carry = shifta(acc(m), digit_bits)
      acc(m) = acc(m) - shiftl(carry, digit_bits)
      acc(m - 1) = acc(m - 1) + carry
    end do
  end subroutine digits_normalize

  !> Sum the digits over all ranks (exact integer arithmetic) and normalise them.
  subroutine reduce_digits(dom, acc)
    type(domain_t), intent(in) :: dom            !< decomposition (its communicator)
    integer(i8), intent(inout) :: acc(:, :)      !< (0:ndigits, n) digits, local in, global out
    integer(i8) :: local(size(acc, 1), size(acc, 2))
    integer :: n
    local(:, :) = acc(:, :)
    call MPI_Allreduce(local, acc, size(acc), MPI_INTEGER8, MPI_SUM, dom%comm)
    do n = 1, size(acc, 2)
      call digits_normalize(acc(:, n))
    end do
  end subroutine reduce_digits

  !> The real value of normalised digits with common exponent `e` (one rounding per digit, smallest
  !! first, on the magnitude; deterministic).
  pure function digits_value(acc, e) result(x)
    integer(i8), intent(in) :: acc(0:ndigits)  !< normalised digits
    integer, intent(in) :: e                   !< common exponent
    real(wp) :: x
    integer(i8) :: work(0:ndigits)
    integer :: m
    real(wp) :: sign_factor
    work(:) = acc(:)
    sign_factor = 1.0_wp
    if (work(0) < 0_i8) then
      work(:) = -work(:)
      call digits_normalize(work)
      sign_factor = -1.0_wp
    end if
    x = 0.0_wp
    do m = ndigits, 0, -1
      x = x + scale(real(work(m), wp), e - digit_bits * m)
    end do
    x = sign_factor * x
  end function digits_value

  ! ------------------------------------------------------------------ exact reductions

  !> Sum of a default integer over all ranks.
  integer function global_sum_int(dom, n) result(total)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    integer, intent(in) :: n           !< this rank's contribution
    total = reduce_int(dom, n, MPI_SUM)
  end function global_sum_int

  !> Sum of a 64-bit integer over all ranks (global counts).
  integer(i8) function global_sum_i8(dom, n) result(total)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    integer(i8), intent(in) :: n       !< this rank's contribution
    call MPI_Allreduce(n, total, 1, MPI_INTEGER8, MPI_SUM, dom%comm)
  end function global_sum_i8

  !> Maximum of a real over all ranks [unit of x].
  real(wp) function global_max_real(dom, x) result(y)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    real(wp), intent(in) :: x          !< this rank's value
    y = reduce_real(dom, x, MPI_MAX)
  end function global_max_real

  !> Minimum of a real over all ranks [unit of x].
  real(wp) function global_min_real(dom, x) result(y)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    real(wp), intent(in) :: x          !< this rank's value
    y = reduce_real(dom, x, MPI_MIN)
  end function global_min_real

  !> Maximum of an integer over all ranks.
  integer function global_max_int(dom, n) result(m)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    integer, intent(in) :: n           !< this rank's value
    m = reduce_int(dom, n, MPI_MAX)
  end function global_max_int

  !> Minimum of an integer over all ranks.
  integer function global_min_int(dom, n) result(m)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    integer, intent(in) :: n           !< this rank's value
    m = reduce_int(dom, n, MPI_MIN)
  end function global_min_int

  !> True on every rank when `flag` is true on at least one rank.
  logical function global_any(dom, flag) result(any_flag)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    logical, intent(in) :: flag        !< this rank's flag
    any_flag = all_or(dom%comm, flag)
  end function global_any

  !> True on every rank when `flag` is true on all ranks.
  logical function global_all(dom, flag) result(all_flag)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    logical, intent(in) :: flag        !< this rank's flag
    all_flag = all_and(dom%comm, flag)
  end function global_all

  !> MPI_Allreduce of one real with the operation `op`.
  real(wp) function reduce_real(dom, x, op) result(y)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    real(wp), intent(in) :: x          !< this rank's value
    type(MPI_Op), intent(in) :: op     !< MPI_MAX or MPI_MIN
    call MPI_Allreduce(x, y, 1, MPI_DOUBLE_PRECISION, op, dom%comm)
  end function reduce_real

  !> MPI_Allreduce of one default integer with the operation `op`.
  integer function reduce_int(dom, n, op) result(m)
    type(domain_t), intent(in) :: dom  !< decomposition (its communicator)
    integer, intent(in) :: n           !< this rank's value
    type(MPI_Op), intent(in) :: op     !< MPI_SUM, MPI_MAX or MPI_MIN
    call MPI_Allreduce(n, m, 1, MPI_INTEGER, op, dom%comm)
  end function reduce_int

end module parallel_reduce
