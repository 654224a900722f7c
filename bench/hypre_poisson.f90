!> Benchmark of the hypre Struct PCG + PFMG solver (`solver_pressure`) on 2D problems with walls:
!! * `mms` (default): the manufactured variable-coefficient Poisson problem of `solver_poisson_mms`
!!   (k = 1 + 0.5 sin sin), with L2 error and observed order;
!! * `jump`: k = 1e-3 in a disc and a bottom layer, 1 elsewhere (a 1000:1 jump, as between water
!!   and air in the pressure equation), f = 1, u = 0 on the walls; no exact solution.
!! For each resolution it prints (and writes to CSV) the PCG iterations, the final relative
!! residual, the error, and the wall-clock times of the first solve (operator assembly + PFMG
!! set-up + solve) and of a repeated solve (solve only, best of `repeats`), both from x = 0.
!!
!! Usage: mpirun -n N hypre_poisson [--problem mms|jump] [--tolerance T] [--csv FILE] [n ...]
!!   defaults: mms, tolerance 1e-10, no CSV, cells per side 32 64 128 256 512.
program hypre_poisson
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_Init, MPI_Finalize, MPI_Comm_dup, &
    MPI_Comm_free, MPI_Comm_rank, MPI_Comm_size, MPI_Barrier, MPI_Wtime
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: fatal
  use mpmice_log, only: log_init
  use parallel_domain, only: grid_init, domain_t, domain_init, domain_free
  use grid_layout, only: grid_t, cell_centre, node_position
  use solver_pressure, only: struct_solver_t, struct_solver_init, struct_solver_set_operator, &
    struct_solver_solve, struct_solver_free
  use solver_poisson_mms, only: mms_build, mms_error_l2
  implicit none

  integer, parameter :: repeats = 3        !< repeated solves timed (best kept)
  integer, parameter :: max_iterations = 500
  type(MPI_Comm) :: comm
  type(domain_t) :: dom
  type(grid_t) :: grid
  type(struct_solver_t) :: solver
  real(wp), allocatable :: diag(:, :, :), cx(:, :, :), cy(:, :, :), cz(:, :, :), rhs(:, :, :)
  real(wp), allocatable :: x(:, :, :)
  integer, allocatable :: sizes(:)
  character(len=path_len) :: csv_path, arg
  real(wp) :: tolerance, error, previous_error, order, residual, t0, t_first, t_solve, per_cell
  character(len=16) :: order_text, error_text
  character(len=8) :: problem
  integer :: rank, nranks, level, its, its_repeat, r, unit, ios, nargs, n
  logical :: converged, write_csv

  call MPI_Init()
  call MPI_Comm_dup(MPI_COMM_WORLD, comm)
  call MPI_Comm_rank(comm, rank)
  call MPI_Comm_size(comm, nranks)
  call log_init(rank == 0)

  nargs = command_argument_count()
  csv_path = ''
  problem = 'mms'
  tolerance = 1.0e-10_wp
  allocate(sizes(0))
  n = 1
  do while (n <= nargs)
    call get_command_argument(n, arg)
    select case (trim(arg))
    case ('--problem')
      n = n + 1
      call get_command_argument(n, problem)
      if (problem /= 'mms' .and. problem /= 'jump') call fatal('unknown problem: ' // trim(problem))
    case ('--tolerance')
      n = n + 1
      call get_command_argument(n, arg)
      read(arg, *, iostat=ios) tolerance
      if (ios /= 0 .or. .not. (tolerance > 0.0_wp)) call fatal('bad tolerance: ' // trim(arg))
    case ('--csv')
      n = n + 1
      call get_command_argument(n, csv_path)
    case default
      read(arg, *, iostat=ios) its
      if (ios /= 0 .or. its < 2) call fatal('bad argument: ' // trim(arg))
      sizes = [sizes, its]
    end select
    n = n + 1
  end do
  if (size(sizes) == 0) sizes = [32, 64, 128, 256, 512]
  write_csv = len_trim(csv_path) > 0

  if (rank == 0) then
    write(*, '(a,a,a,i0,a,es8.1)') 'hypre PCG+PFMG, 2D problem ', trim(problem), ', ranks = ', &
      nranks, ', tolerance = ', tolerance
    write(*, '(a6,a10,a6,a11,a12,a7,a11,a11,a12)') 'n', 'cells', 'iters', 'rel.resid', &
      'L2 error', 'order', 't_first/s', 't_solve/s', 'us/cell/it'
    if (write_csv) then
      open(newunit=unit, file=trim(csv_path), status='replace', action='write', iostat=ios)
      if (ios /= 0) call fatal('cannot open ' // trim(csv_path))
      write(unit, '(a)') 'problem,ranks,n,cells,iterations,relative_residual,l2_error,' // &
        'observed_order,time_first_s,time_solve_s,us_per_cell_iteration'
    end if
  end if

  previous_error = -1.0_wp
  do level = 1, size(sizes)
    n = sizes(level)
    call domain_init(dom, comm, [n, n, 1], [.false., .false., .false.], 1)
    call grid_init(grid, dom, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp])
    associate (lb => grid%lbc, ub => grid%ubc)
      allocate(diag(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), cx(lb(1):ub(1), lb(2):ub(2), &
        lb(3):ub(3)), cy(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), cz(lb(1):ub(1), lb(2):ub(2), &
        lb(3):ub(3)), rhs(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)))
      allocate(x(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), source=0.0_wp)
    end associate
    if (problem == 'mms') then
      call mms_build(grid, 0.0_wp, diag, cx, cy, cz, rhs)
    else
      call jump_build(grid, diag, cx, cy, cz, rhs)
    end if
    call struct_solver_init(solver, dom, grid, tolerance, max_iterations, 0)

    call MPI_Barrier(comm)
    t0 = MPI_Wtime()
    call struct_solver_set_operator(solver, grid, diag, cx, cy, cz)
    call struct_solver_solve(solver, grid, rhs, x, its, residual, converged)
    call MPI_Barrier(comm)
    t_first = MPI_Wtime() - t0
    if (.not. converged) call fatal('benchmark solve did not converge')
    error = -1.0_wp
    if (problem == 'mms') error = mms_error_l2(grid, dom%comm, x)

    t_solve = huge(1.0_wp)
    do r = 1, repeats
      x = 0.0_wp
      call MPI_Barrier(comm)
      t0 = MPI_Wtime()
      call struct_solver_solve(solver, grid, rhs, x, its_repeat, residual, converged)
      call MPI_Barrier(comm)
      t_solve = min(t_solve, MPI_Wtime() - t0)
      if (its_repeat /= its) call fatal('repeated solve took a different number of iterations')
    end do

    ! observed order against the previous resolution (sizes are expected to double)
    order_text = ''
    error_text = ''
    if (error >= 0.0_wp) write(error_text, '(es11.5)') error
    if (previous_error > 0.0_wp .and. error > 0.0_wp) then
      order = log(previous_error / error) / log(real(n, wp) / real(sizes(level - 1), wp))
      write(order_text, '(f0.3)') order
    end if
    per_cell = 1.0e6_wp * t_solve / (real(n, wp)**2 * real(max(its, 1), wp))
    if (rank == 0) then
      write(*, '(i6,i10,i6,es11.3,a12,a7,f11.5,f11.5,f12.5)') n, n * n, its, residual, &
        trim(error_text), trim(order_text), t_first, t_solve, per_cell
      if (write_csv) write(unit, '(a,",",i0,",",i0,",",i0,",",i0,",",es11.5,",",a,",",a,",",' // &
        'es11.5,",",es11.5,",",es11.5)') trim(problem), nranks, n, n * n, its, residual, &
        trim(error_text), trim(order_text), t_first, t_solve, per_cell
    end if
    previous_error = error

    call struct_solver_free(solver)
    call domain_free(dom)
    deallocate(diag, cx, cy, cz, rhs, x)
  end do

  if (rank == 0 .and. write_csv) close(unit)
  call MPI_Comm_free(comm)
  call MPI_Finalize()

contains

  !> The `jump` problem: k = 1e-3 in the disc |x - (0.4, 0.55)| < 0.2 and below y = 0.3, 1
  !! elsewhere (evaluated at face centres), f = 1, u = 0 on the walls (half-cell distance).
  subroutine jump_build(grid, diag, coef_x, coef_y, coef_z, rhs)
    type(grid_t), intent(in) :: grid   !< block geometry
    real(wp), intent(out) :: diag(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< centre
    real(wp), intent(out) :: coef_x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< x low faces
    real(wp), intent(out) :: coef_y(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< y low faces
    real(wp), intent(out) :: coef_z(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< unused (2D)
    real(wp), intent(out) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)    !< right-hand side
    integer :: i, j, d, side, face, cell(3)
    real(wp) :: p(2), c
    diag = 0.0_wp
    coef_x = 0.0_wp
    coef_y = 0.0_wp
    coef_z = 0.0_wp
    rhs = 0.0_wp
    do j = grid%lo(2), grid%hi(2)
      do i = grid%lo(1), grid%hi(1)
        cell = [i, j, 1]
        rhs(i, j, 1) = 1.0_wp
        do d = 1, 2
          do side = 0, 1
            face = cell(d) + side
            p = [cell_centre(grid, 1, i), cell_centre(grid, 2, j)]
            p(d) = node_position(grid, d, face)
            c = 1.0_wp
            if ((p(1) - 0.4_wp)**2 + (p(2) - 0.55_wp)**2 < 0.04_wp .or. p(2) < 0.3_wp) then
              c = 1.0e-3_wp
            end if
            c = c / grid%dx(d)**2
            if (face == 1 .or. face == grid%ncells(d) + 1) then
              diag(i, j, 1) = diag(i, j, 1) + 2.0_wp * c
            else
              diag(i, j, 1) = diag(i, j, 1) + c
              if (side == 0 .and. d == 1) coef_x(i, j, 1) = c
              if (side == 0 .and. d == 2) coef_y(i, j, 1) = c
            end if
          end do
        end do
      end do
    end do
  end subroutine jump_build
end program hypre_poisson
