!> Symmetric positive definite cell-centred systems on the block-structured grid, solved by hypre
!! Struct PCG preconditioned by one PFMG multigrid V-cycle (design §4). Used for the pressure
!! equation (paper eq. 35) and for implicit conduction.
!!
!! The operator, for every owned cell c (global indices, arrays with the grid's cell bounds):
!!   (A x)_c = diag_c x_c - sum_{faces f of c} coef_f x_{neighbour across f},
!! with `coef_d(i,j,k)` the coefficient of the LOW face of cell (i,j,k) in direction d. The high
!! face of a cell is the low face of its neighbour, so the operator is symmetric by construction;
!! it is positive definite when diag >= sum of the face coefficients of the cell with strict
!! inequality somewhere (a wall or a reaction term). Boundary conditions are the caller's: a face
!! on a non-periodic domain boundary does not couple to anything (its entry in `coef_d` is ignored),
!! Dirichlet/Neumann conditions are folded into `diag` and the right-hand side. In a periodic
!! dimension the low face of cell 1 couples to cell `ncells`.
!!
!! hypre side: one box per rank (the owned cells), the active dimensions of the grid mapped in
!! order onto hypre's dimensions 1..ndim (hypre index = global cell index - 1, so a periodic box
!! starts at 0; a 1D problem is posed as a one-cell-thick 2D one because PFMG only supports 2D
!! and 3D stencils), a symmetric matrix storing the centre and the low neighbour per dimension
!! (`HYPRE_StructMatrixSetSymmetric`), and PCG (relative two-norm residual) preconditioned by one
!! PFMG V-cycle (zero initial guess, tolerance 0, red-black Gauss-Seidel, forward before and
!! backward after the coarse-grid correction, hypre's non-Galerkin 7-point coarse operators, the
!! ones red-black relaxation works with; two sweeps each on every level in 3D, one sweep each
!! with hypre's level skipping in 2D with square cells, one sweep each on every level
!! otherwise: `pfmg_cycle`): a symmetric preconditioner, as PCG needs. On the two-fluid 50^3
!! pressure equation (1000:1 density jump) it takes half the time of weighted Jacobi with
!! Galerkin coarse operators; on a 2D 1000:1 coefficient jump its iterations grow with
!! resolution, 17 to 27 from 32^2 to 512^2 (docs/hypre.md).
!! Changing the operator values rebuilds the PFMG hierarchy at the next solve (hypre's PFMG cannot
!! be set up twice), nothing else is reallocated. `struct_solver_set_reuse(solver, n)` keeps a
!! hierarchy for up to n solves across operator changes (default 1: rebuild after every change),
!! and rebuilds earlier when a solve needed more than 1.5 times the PCG iterations of the first
!! solve after the set-up. PCG stays correct with the stale SPD preconditioner and still iterates
!! to the tolerance.
!! `struct_solver_invalidate` forces a rebuild at the next solve (scenes call it when they write a
!! checkpoint, so that a restarted run rebuilds at the same solve as the continuing run).
!!
!! Direct fast path (`solver_line`): when the whole operator is one line on this rank (one
!! active grid dimension and one rank), it is factorised in `set_operator` and solved directly
!! (0 iterations); hypre is kept for everything else, and as a fallback should the factorisation
!! meet a non-positive pivot.
module solver_pressure
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_null_ptr, c_associated, &
    c_funloc
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use parallel_comm, only: MPI_Comm, sum_in_place
  use mpmice_kinds, only: wp, msg_len
  use mpmice_errors, only: fatal
  use mpmice_log, only: log_warning
  use parallel_domain, only: domain_t
  use grid_layout, only: grid_t
  use solver_box, only: check_bounds, pack_owned, unpack_owned
  use solver_pfmg, only: pfmg_relax_type, pfmg_rap_type, pfmg_cycle
  use solver_line, only: line_solver_t, line_init, line_free, line_factor, line_solve
  use solver_hypre_api, only: hypre_c_comm, hypre_check, HYPRE_ERROR_CONV, HYPRE_Init, &
    HYPRE_ClearError, HYPRE_ERROR_GENERIC, HYPRE_ClearAllErrors, &
    HYPRE_StructGridCreate, HYPRE_StructGridDestroy, HYPRE_StructGridSetExtents, &
    HYPRE_StructGridSetPeriodic, HYPRE_StructGridAssemble, &
    HYPRE_StructStencilCreate, HYPRE_StructStencilDestroy, HYPRE_StructStencilSetElement, &
    HYPRE_StructMatrixCreate, HYPRE_StructMatrixDestroy, HYPRE_StructMatrixSetSymmetric, &
    HYPRE_StructMatrixInitialize, HYPRE_StructMatrixSetBoxValues, HYPRE_StructMatrixAssemble, &
    HYPRE_StructVectorCreate, HYPRE_StructVectorDestroy, HYPRE_StructVectorInitialize, &
    HYPRE_StructVectorSetBoxValues, HYPRE_StructVectorGetBoxValues, HYPRE_StructVectorAssemble, &
    HYPRE_StructPCGCreate, HYPRE_StructPCGDestroy, HYPRE_StructPCGSetTol, &
    HYPRE_StructPCGSetMaxIter, HYPRE_StructPCGSetTwoNorm, HYPRE_StructPCGSetRelChange, &
    HYPRE_StructPCGSetPrintLevel, HYPRE_StructPCGSetLogging, HYPRE_StructPCGSetPrecond, &
    HYPRE_StructPCGSetup, HYPRE_StructPCGSolve, HYPRE_StructPCGGetNumIterations, &
    HYPRE_StructPCGGetFinalRelativeResidualNorm, &
    HYPRE_StructPFMGCreate, HYPRE_StructPFMGDestroy, HYPRE_StructPFMGSetMaxIter, &
    HYPRE_StructPFMGSetTol, HYPRE_StructPFMGSetZeroGuess, HYPRE_StructPFMGSetRelaxType, &
    HYPRE_StructPFMGSetRAPType, HYPRE_StructPFMGSetNumPreRelax, HYPRE_StructPFMGSetNumPostRelax, &
    HYPRE_StructPFMGSetSkipRelax, HYPRE_StructPFMGSetPrintLevel, HYPRE_StructPFMGSetLogging, &
    HYPRE_StructPFMGSetup, HYPRE_StructPFMGSolve
  implicit none
  private

  public :: struct_solver_t, struct_solver_init, struct_solver_set_operator, struct_solver_solve
  public :: struct_solver_free, struct_solver_set_reuse, struct_solver_invalidate

  !> hypre objects, index maps and work buffers of one structured SPD solver.
  type :: struct_solver_t
    type(c_ptr) :: comm = c_null_ptr      !< C handle of the domain communicator (not owned)
    type(c_ptr) :: grid = c_null_ptr      !< HYPRE_StructGrid
    type(c_ptr) :: stencil = c_null_ptr   !< HYPRE_StructStencil
    type(c_ptr) :: matrix = c_null_ptr    !< HYPRE_StructMatrix (symmetric storage)
    type(c_ptr) :: b = c_null_ptr         !< HYPRE_StructVector, right-hand side
    type(c_ptr) :: x = c_null_ptr         !< HYPRE_StructVector, solution
    type(c_ptr) :: pcg = c_null_ptr       !< HYPRE_StructSolver, PCG
    type(c_ptr) :: pfmg = c_null_ptr      !< HYPRE_StructSolver, PFMG preconditioner
    type(MPI_Comm) :: fcomm               !< domain communicator (for reductions; not owned)
    integer :: ndim = 2                   !< hypre dimensions (active grid dimensions, at least 2)
    integer :: dims(3) = 0                !< grid dimension of hypre dimension 1..ndim
    integer :: lo(3) = 1                  !< first owned cell (global index)
    integer :: hi(3) = 1                  !< last owned cell (global index)
    integer :: ncells(3) = 1              !< global cells per dimension
    logical :: periodic(3) = .false.      !< periodic grid dimensions
    integer(c_int) :: ilower(3) = 0       !< hypre box lower corner
    integer(c_int) :: iupper(3) = 0       !< hypre box upper corner
    integer(c_int) :: nentries = 0        !< stored stencil entries (1 + ndim)
    integer(c_int) :: entries(4) = 0      !< stencil entry numbers 0..ndim
    integer(c_int) :: sweeps = 1_c_int    !< PFMG sweeps before and after the coarse correction
    integer(c_int) :: skip_relax = 0_c_int !< PFMG skips the relaxation on some levels (1) or not
    integer :: nowned = 0                 !< owned cells
    real(c_double), allocatable :: matrix_values(:)  !< (nentries*nowned) box values of A
    real(c_double), allocatable :: vector_values(:)  !< (nowned) box values of b or x
    real(wp) :: tolerance = 1.0e-10_wp    !< relative residual tolerance ||r||_2/||b||_2
    integer :: max_iterations = 200       !< PCG iteration limit
    integer :: print_level = 0            !< hypre PCG print level (0 silent)
    logical :: operator_set = .false.     !< struct_solver_set_operator has been called
    logical :: setup_done = .false.       !< PCG/PFMG exist and are set up (maybe for an older operator)
    logical :: operator_changed = .false. !< the operator changed since the PFMG set-up
    integer :: reuse = 1                  !< PFMG set-up kept for up to this many solves (>= 1)
    integer :: uses = 0                   !< hypre solves done with the current PFMG set-up
    integer :: setups = 0                 !< PFMG set-ups done since init (diagnostics)
    integer :: setup_iterations = 0       !< PCG iterations of the first full-tolerance solve
                                          !! after the set-up (0: none yet)
    integer :: last_iterations = 0        !< PCG iterations of the last full-tolerance solve
    ! direct path: one tridiagonal line on this rank
    logical :: direct = .false.           !< the operator is one line on this rank
    type(line_solver_t) :: line           !< its factorisation (`line%ready`: valid)
    logical :: initialized = .false.      !< set by struct_solver_init
  end type struct_solver_t

contains

  !> Build the hypre grid (this rank's owned cells), stencil, matrix, vectors and work buffers,
  !! and store the PCG controls (namelist `&solver`). Collective over `dom%comm`, which must
  !! outlive the solver.
  subroutine struct_solver_init(solver, dom, grid, tolerance, max_iterations, print_level, direct)
    type(struct_solver_t), intent(inout) :: solver  !< solver to build (freed first)
    type(domain_t), intent(in) :: dom               !< decomposition (communicator)
    type(grid_t), intent(in) :: grid                !< block geometry and index ranges
    real(wp), intent(in) :: tolerance               !< relative residual tolerance, > 0
    integer, intent(in) :: max_iterations           !< PCG iteration limit, >= 1
    integer, intent(in) :: print_level              !< hypre PCG print level (0 silent)
    !> allow the direct tridiagonal path (default true; false forces hypre, for tests)
    logical, intent(in), optional :: direct
    integer(c_int) :: offset(3), period(3)
    integer :: d, n

    call struct_solver_free(solver)
    if (.not. dom%initialized) call fatal('struct_solver_init: domain not initialised')
    if (.not. (tolerance > 0.0_wp)) call fatal('struct_solver_init: tolerance must be > 0')
    if (max_iterations < 1) call fatal('struct_solver_init: max_iterations must be >= 1')
    if (any(dom%lo /= grid%lo) .or. any(dom%hi /= grid%hi)) then
      call fatal('struct_solver_init: grid does not belong to the domain')
    end if

    solver%tolerance = tolerance
    solver%max_iterations = max_iterations
    solver%print_level = print_level
    solver%fcomm = dom%comm
    solver%comm = hypre_c_comm(dom%comm)
    solver%lo = grid%lo
    solver%hi = grid%hi
    solver%ncells = grid%ncells
    solver%periodic = grid%periodic .and. grid%active

    ! active grid dimensions -> hypre dimensions 1..ndim, padded with inactive (one-cell)
    ! dimensions up to 2: PFMG handles 2D and 3D stencils only
    n = 0
    do d = 1, 3
      if (grid%active(d)) then
        n = n + 1
        solver%dims(n) = d
      end if
    end do
    do d = 1, 3
      if (n >= 2) exit
      if (.not. grid%active(d)) then
        n = n + 1
        solver%dims(n) = d
      end if
    end do
    solver%ndim = n
    solver%nentries = int(n + 1, c_int)
    call pfmg_cycle(grid, solver%sweeps, solver%skip_relax)
    period = 0
    do d = 1, n
      solver%ilower(d) = int(grid%lo(solver%dims(d)) - 1, c_int)
      solver%iupper(d) = int(grid%hi(solver%dims(d)) - 1, c_int)
      if (solver%periodic(solver%dims(d))) period(d) = int(grid%ncells(solver%dims(d)), c_int)
    end do
    solver%nowned = product(grid%hi - grid%lo + 1)

    call hypre_check(HYPRE_Init(), 'HYPRE_Init')
    call hypre_check(HYPRE_StructGridCreate(solver%comm, int(n, c_int), solver%grid), &
      'HYPRE_StructGridCreate')
    call hypre_check(HYPRE_StructGridSetExtents(solver%grid, solver%ilower, solver%iupper), &
      'HYPRE_StructGridSetExtents')
    if (any(period /= 0)) then
      call hypre_check(HYPRE_StructGridSetPeriodic(solver%grid, period), &
        'HYPRE_StructGridSetPeriodic')
    end if
    call hypre_check(HYPRE_StructGridAssemble(solver%grid), 'HYPRE_StructGridAssemble')

    ! stencil entry 0: centre; entry d: low neighbour in hypre dimension d
    call hypre_check(HYPRE_StructStencilCreate(int(n, c_int), solver%nentries, solver%stencil), &
      'HYPRE_StructStencilCreate')
    do d = 0, n
      offset = 0
      offset(max(d, 1)) = -min(d, 1)
      solver%entries(d + 1) = int(d, c_int)
      call hypre_check(HYPRE_StructStencilSetElement(solver%stencil, int(d, c_int), offset), &
        'HYPRE_StructStencilSetElement')
    end do

    call hypre_check(HYPRE_StructMatrixCreate(solver%comm, solver%grid, solver%stencil, &
      solver%matrix), 'HYPRE_StructMatrixCreate')
    call hypre_check(HYPRE_StructMatrixSetSymmetric(solver%matrix, 1_c_int), &
      'HYPRE_StructMatrixSetSymmetric')
    call hypre_check(HYPRE_StructMatrixInitialize(solver%matrix), 'HYPRE_StructMatrixInitialize')

    call hypre_check(HYPRE_StructVectorCreate(solver%comm, solver%grid, solver%b), &
      'HYPRE_StructVectorCreate')
    call hypre_check(HYPRE_StructVectorInitialize(solver%b), 'HYPRE_StructVectorInitialize')
    call hypre_check(HYPRE_StructVectorCreate(solver%comm, solver%grid, solver%x), &
      'HYPRE_StructVectorCreate')
    call hypre_check(HYPRE_StructVectorInitialize(solver%x), 'HYPRE_StructVectorInitialize')

    allocate(solver%matrix_values(solver%nentries * solver%nowned))
    allocate(solver%vector_values(solver%nowned))

    ! one active dimension on one rank: the operator is a single tridiagonal line
    solver%direct = dom%nranks == 1 .and. count(grid%active) == 1
    if (present(direct)) solver%direct = solver%direct .and. direct
    if (solver%direct) then
      call line_init(solver%line, solver%nowned, solver%periodic(solver%dims(1)))
    end if
    solver%operator_set = .false.
    solver%setup_done = .false.
    solver%operator_changed = .false.
    solver%reuse = 1
    solver%uses = 0
    solver%setups = 0
    solver%setup_iterations = 0
    solver%last_iterations = 0
    solver%initialized = .true.
  end subroutine struct_solver_init

  !> Set (or reset) the operator values: centre `diag` and low-face couplings `coef_x/y/z`
  !! (see the module header for the sign convention). Only owned cells are read; arrays of
  !! inactive dimensions are ignored, and so are faces on non-periodic domain boundaries.
  subroutine struct_solver_set_operator(solver, grid, diag, coef_x, coef_y, coef_z)
    type(struct_solver_t), intent(inout) :: solver  !< initialised solver
    type(grid_t), intent(in) :: grid                !< block geometry (as at init)
    real(wp), intent(in) :: diag(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< centre [any]
    real(wp), intent(in) :: coef_x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< x low face [same]
    real(wp), intent(in) :: coef_y(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< y low face [same]
    real(wp), intent(in) :: coef_z(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< z low face [same]
    integer :: i, j, k, d, g, m, cell(3)
    real(wp) :: c

    call check_ready(solver, grid, 'struct_solver_set_operator', .false.)
    call check_bounds(grid, ubound(diag), 'diag')
    call check_bounds(grid, ubound(coef_x), 'coef_x')
    call check_bounds(grid, ubound(coef_y), 'coef_y')
    call check_bounds(grid, ubound(coef_z), 'coef_z')
    m = 0
    do k = solver%lo(3), solver%hi(3)
      do j = solver%lo(2), solver%hi(2)
        do i = solver%lo(1), solver%hi(1)
          cell = [i, j, k]
          solver%matrix_values(m + 1) = real(diag(i, j, k), c_double)
          do d = 1, solver%ndim
            g = solver%dims(d)
            if (cell(g) == 1 .and. .not. solver%periodic(g)) then
              c = 0.0_wp
            else if (g == 1) then
              c = coef_x(i, j, k)
            else if (g == 2) then
              c = coef_y(i, j, k)
            else
              c = coef_z(i, j, k)
            end if
            solver%matrix_values(m + 1 + d) = real(-c, c_double)
          end do
          m = m + solver%nentries
        end do
      end do
    end do
    solver%operator_set = .true.
    if (solver%direct) then
      call line_factor(solver%line, solver%matrix_values, solver%nentries)
      if (solver%line%ready) return
    end if
    call hypre_check(HYPRE_StructMatrixSetBoxValues(solver%matrix, solver%ilower, solver%iupper, &
      solver%nentries, solver%entries, solver%matrix_values), 'HYPRE_StructMatrixSetBoxValues')
    call hypre_check(HYPRE_StructMatrixAssemble(solver%matrix), 'HYPRE_StructMatrixAssemble')
    solver%operator_changed = .true.
  end subroutine struct_solver_set_operator

  !> Keep the PFMG hierarchy for up to `n` solves across operator changes (n = 1, the default set
  !! by `struct_solver_init`: rebuild at the first solve after every `set_operator`). The
  !! hierarchy is rebuilt earlier, at the next solve after an operator change, once a solve
  !! took more than 1.5 times the PCG iterations of the first solve after the set-up. A solve
  !! with an unchanged operator never rebuilds. Call after `struct_solver_init`.
  subroutine struct_solver_set_reuse(solver, n)
    type(struct_solver_t), intent(inout) :: solver  !< initialised solver
    integer, intent(in) :: n                        !< solves per PFMG set-up, >= 1
    if (.not. solver%initialized) call fatal('struct_solver_set_reuse: solver not initialised')
    if (n < 1) call fatal('struct_solver_set_reuse: n must be >= 1')
    solver%reuse = n
  end subroutine struct_solver_set_reuse

  !> Force a PFMG rebuild at the next solve and restart the reuse count. ICE calls it at the start
  !! of every pressure stage, the heat scene when it writes a checkpoint: a run restarted from a
  !! checkpoint starts with a fresh solver, so both runs then rebuild at the same solve and
  !! continue bitwise identically. No effect on the
  !! direct path, whose factorisation always belongs to the current operator.
  subroutine struct_solver_invalidate(solver)
    type(struct_solver_t), intent(inout) :: solver  !< solver (initialised or not)
    solver%setup_done = .false.
    solver%uses = 0
    solver%setup_iterations = 0
    solver%last_iterations = 0
  end subroutine struct_solver_invalidate

  !> Solve A x = rhs by PCG + PFMG with `x` as initial guess (owned cells read and written,
  !! ghosts untouched). `converged` is false when the relative residual ||r||_2/||b||_2 did not
  !! reach the tolerance within `max_iterations`; a warning naming the iterations and the residual
  !! is then logged. A zero right-hand side gives x = 0 without iterating. With
  !! `absolute_tolerance` the PCG also stops once ||r||_2 <= absolute_tolerance (global 2-norm, in
  !! the units of `rhs`): its relative tolerance for this solve is then
  !! max(tolerance, absolute_tolerance / ||b||_2), and `converged` refers to that. Collective.
  subroutine struct_solver_solve(solver, grid, rhs, x, iterations, relative_residual, converged, &
      absolute_tolerance)
    type(struct_solver_t), intent(inout) :: solver  !< solver with an operator set
    type(grid_t), intent(in) :: grid                !< block geometry (as at init)
    real(wp), intent(in) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)  !< right-hand side
    real(wp), intent(inout) :: x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< guess in, solution out
    integer, intent(out) :: iterations             !< PCG iterations done
    real(wp), intent(out) :: relative_residual     !< final ||r||_2/||b||_2
    logical, intent(out) :: converged              !< tolerance reached
    !> stop also at ||r||_2 <= this (units of `rhs`; default 0: the relative tolerance alone)
    real(wp), intent(in), optional :: absolute_tolerance
    integer(c_int) :: ierr, its
    real(c_double) :: norm
    real(wp) :: bb(2), tolerance
    character(len=msg_len) :: text

    call check_ready(solver, grid, 'struct_solver_solve', .true.)
    call check_bounds(grid, ubound(rhs), 'rhs')
    call check_bounds(grid, ubound(x), 'x')

    if (solver%line%ready) then
      ! the direct solve is exact to round-off: no looser tolerance needed
      call solve_line(solver, grid, rhs, x, relative_residual)
      iterations = 0
      converged = relative_residual <= solver%tolerance   ! false for NaN as well
      if (.not. converged) then
        write(text, '(a,es10.3,a,es10.3)') 'struct solver (direct tridiagonal): relative ' // &
          'residual ', relative_residual, ' > tolerance ', solver%tolerance
        call log_warning(trim(text))
      end if
      return
    end if

    call pack_owned(grid, rhs, solver%vector_values)
    bb = 0.0_wp
    if (solver%nowned > 0) bb(1) = real(dot_product(solver%vector_values, solver%vector_values), wp)
    ! non-finite operator entries of this rank (hypre would stop with an error on them)
    bb(2) = real(count(.not. ieee_is_finite(solver%matrix_values)), wp)
    call sum_in_place(solver%fcomm, bb)
    if (.not. ieee_is_finite(bb(1)) .or. bb(2) > 0.0_wp) then
      ! a NaN or Inf in the system: no solve; x is NaN in the cells whose equation holds one, so
      ! the caller sees where (ice_stage_pressure ends the step, the run fails with a dump)
      call mark_nonfinite(solver, grid, rhs, x)
      iterations = 0
      relative_residual = ieee_value(1.0_wp, ieee_quiet_nan)
      converged = .false.
      return
    end if
    if (bb(1) == 0.0_wp) then
      solver%vector_values = 0.0_c_double
      call unpack_owned(grid, solver%vector_values, x)
      iterations = 0
      relative_residual = 0.0_wp
      converged = .true.
      return
    end if
    call hypre_check(HYPRE_StructVectorSetBoxValues(solver%b, solver%ilower, solver%iupper, &
      solver%vector_values), 'HYPRE_StructVectorSetBoxValues')
    call hypre_check(HYPRE_StructVectorAssemble(solver%b), 'HYPRE_StructVectorAssemble')
    call pack_owned(grid, x, solver%vector_values)
    call hypre_check(HYPRE_StructVectorSetBoxValues(solver%x, solver%ilower, solver%iupper, &
      solver%vector_values), 'HYPRE_StructVectorSetBoxValues')
    call hypre_check(HYPRE_StructVectorAssemble(solver%x), 'HYPRE_StructVectorAssemble')

    if (.not. solver%setup_done) then
      call setup_krylov(solver)
    else if (solver%operator_changed .and. (solver%uses >= solver%reuse .or. &
      (solver%setup_iterations > 0 .and. &
      2 * solver%last_iterations > 3 * solver%setup_iterations))) then
      ! reuse spent, or the stale hierarchy already cost 1.5 times the iterations of its first
      ! solve (deterministic: iteration counts only)
      call setup_krylov(solver)
    end if
    solver%uses = solver%uses + 1
    tolerance = solver%tolerance
    if (present(absolute_tolerance)) tolerance = max(tolerance, absolute_tolerance / sqrt(bb(1)))
    call hypre_check(HYPRE_StructPCGSetTol(solver%pcg, real(tolerance, c_double)), &
      'HYPRE_StructPCGSetTol')

    ! hypre flags a PCG that stopped short of the tolerance with HYPRE_ERROR_CONV: not fatal
    ! here, it is reported below from the residual; any other bit is.
    ierr = HYPRE_StructPCGSolve(solver%pcg, solver%matrix, solver%b, solver%x)
    if (iand(ierr, HYPRE_ERROR_CONV) /= 0) then
      ierr = HYPRE_ClearError(HYPRE_ERROR_CONV)
    end if
    if (iand(ierr, HYPRE_ERROR_GENERIC) /= 0) then
      ! PCG stops with this flag (on every rank: its norms are global) when it meets a NaN or
      ! an Inf, which finite data can still produce by overflow: a non-finite result for the
      ! caller, like a system with a NaN (above), not an internal error
      ierr = HYPRE_ClearAllErrors()
      x(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), grid%lo(3):grid%hi(3)) = &
        ieee_value(1.0_wp, ieee_quiet_nan)
      iterations = 0
      relative_residual = ieee_value(1.0_wp, ieee_quiet_nan)
      converged = .false.
      return
    end if
    call hypre_check(ierr, 'HYPRE_StructPCGSolve')
    call hypre_check(HYPRE_StructPCGGetNumIterations(solver%pcg, its), &
      'HYPRE_StructPCGGetNumIterations')
    call hypre_check(HYPRE_StructPCGGetFinalRelativeResidualNorm(solver%pcg, norm), &
      'HYPRE_StructPCGGetFinalRelativeResidualNorm')
    call hypre_check(HYPRE_StructVectorGetBoxValues(solver%x, solver%ilower, solver%iupper, &
      solver%vector_values), 'HYPRE_StructVectorGetBoxValues')
    call unpack_owned(grid, solver%vector_values, x)

    iterations = int(its)
    relative_residual = real(norm, wp)
    if (tolerance == solver%tolerance) then
      ! the reuse test compares full-tolerance solves only (a looser solve stops earlier)
      solver%last_iterations = iterations
      if (solver%setup_iterations == 0) solver%setup_iterations = iterations
    end if
    converged = relative_residual <= tolerance   ! false for NaN as well
    if (.not. converged) then
      write(text, '(a,i0,a,es10.3,a,es10.3)') 'struct solver (PCG+PFMG) did not converge: ', &
        iterations, ' iterations, relative residual ', relative_residual, ' > tolerance ', &
        tolerance
      call log_warning(trim(text))
    end if
  end subroutine struct_solver_solve

  !> x = NaN in the owned cells whose right-hand side (or its square) or operator row is not
  !! finite, 0 in the others (a system with a NaN or Inf is not solved); NaN everywhere when no
  !! cell of any rank is to blame (the sum of squares overflowed). Collective.
  subroutine mark_nonfinite(solver, grid, rhs, x)
    type(struct_solver_t), intent(in) :: solver     !< solver with an operator set
    type(grid_t), intent(in) :: grid                !< block geometry
    real(wp), intent(in) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)  !< right-hand side
    real(wp), intent(inout) :: x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< result
    integer :: i, j, k, m, width
    real(wp) :: nan, marked(1)
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    width = solver%nentries
    marked = 0.0_wp
    m = 0
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          x(i, j, k) = 0.0_wp
          if (.not. ieee_is_finite(rhs(i, j, k)**2) .or. &
            .not. all(ieee_is_finite(solver%matrix_values(m + 1:m + width)))) then
            x(i, j, k) = nan
            marked(1) = marked(1) + 1.0_wp
          end if
          m = m + width
        end do
      end do
    end do
    call sum_in_place(solver%fcomm, marked)
    if (marked(1) == 0.0_wp) x(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), &
      grid%lo(3):grid%hi(3)) = nan
  end subroutine mark_nonfinite

  !> Destroy the hypre objects and release the buffers (safe on a solver never initialised).
  subroutine struct_solver_free(solver)
    type(struct_solver_t), intent(inout) :: solver  !< solver to release
    call destroy_krylov(solver)
    if (c_associated(solver%x)) call hypre_check(HYPRE_StructVectorDestroy(solver%x), &
      'HYPRE_StructVectorDestroy')
    solver%x = c_null_ptr
    if (c_associated(solver%b)) call hypre_check(HYPRE_StructVectorDestroy(solver%b), &
      'HYPRE_StructVectorDestroy')
    solver%b = c_null_ptr
    if (c_associated(solver%matrix)) call hypre_check(HYPRE_StructMatrixDestroy(solver%matrix), &
      'HYPRE_StructMatrixDestroy')
    solver%matrix = c_null_ptr
    if (c_associated(solver%stencil)) call hypre_check( &
      HYPRE_StructStencilDestroy(solver%stencil), 'HYPRE_StructStencilDestroy')
    solver%stencil = c_null_ptr
    if (c_associated(solver%grid)) call hypre_check(HYPRE_StructGridDestroy(solver%grid), &
      'HYPRE_StructGridDestroy')
    solver%grid = c_null_ptr
    solver%comm = c_null_ptr
    if (allocated(solver%matrix_values)) deallocate(solver%matrix_values)
    if (allocated(solver%vector_values)) deallocate(solver%vector_values)
    call line_free(solver%line)
    solver%direct = .false.
    solver%operator_set = .false.
    solver%initialized = .false.
  end subroutine struct_solver_free

  ! ------------------------------------------------------------------ private helpers

  !> Create PCG and its PFMG preconditioner for the current operator and set them up.
  subroutine setup_krylov(solver)
    type(struct_solver_t), intent(inout) :: solver  !< solver with an assembled operator
    call destroy_krylov(solver)
    call hypre_check(HYPRE_StructPFMGCreate(solver%comm, solver%pfmg), 'HYPRE_StructPFMGCreate')
    call hypre_check(HYPRE_StructPFMGSetMaxIter(solver%pfmg, 1_c_int), 'HYPRE_StructPFMGSetMaxIter')
    call hypre_check(HYPRE_StructPFMGSetTol(solver%pfmg, 0.0_c_double), 'HYPRE_StructPFMGSetTol')
    call hypre_check(HYPRE_StructPFMGSetZeroGuess(solver%pfmg), 'HYPRE_StructPFMGSetZeroGuess')
    call hypre_check(HYPRE_StructPFMGSetRelaxType(solver%pfmg, pfmg_relax_type), &
      'HYPRE_StructPFMGSetRelaxType')
    call hypre_check(HYPRE_StructPFMGSetRAPType(solver%pfmg, pfmg_rap_type), &
      'HYPRE_StructPFMGSetRAPType')
    call hypre_check(HYPRE_StructPFMGSetNumPreRelax(solver%pfmg, solver%sweeps), &
      'HYPRE_StructPFMGSetNumPreRelax')
    call hypre_check(HYPRE_StructPFMGSetNumPostRelax(solver%pfmg, solver%sweeps), &
      'HYPRE_StructPFMGSetNumPostRelax')
    call hypre_check(HYPRE_StructPFMGSetSkipRelax(solver%pfmg, solver%skip_relax), &
      'HYPRE_StructPFMGSetSkipRelax')
    call hypre_check(HYPRE_StructPFMGSetPrintLevel(solver%pfmg, 0_c_int), &
      'HYPRE_StructPFMGSetPrintLevel')
    call hypre_check(HYPRE_StructPFMGSetLogging(solver%pfmg, 0_c_int), 'HYPRE_StructPFMGSetLogging')

    call hypre_check(HYPRE_StructPCGCreate(solver%comm, solver%pcg), 'HYPRE_StructPCGCreate')
    call hypre_check(HYPRE_StructPCGSetTol(solver%pcg, real(solver%tolerance, c_double)), &
      'HYPRE_StructPCGSetTol')
    call hypre_check(HYPRE_StructPCGSetMaxIter(solver%pcg, int(solver%max_iterations, c_int)), &
      'HYPRE_StructPCGSetMaxIter')
    call hypre_check(HYPRE_StructPCGSetTwoNorm(solver%pcg, 1_c_int), 'HYPRE_StructPCGSetTwoNorm')
    call hypre_check(HYPRE_StructPCGSetRelChange(solver%pcg, 0_c_int), &
      'HYPRE_StructPCGSetRelChange')
    call hypre_check(HYPRE_StructPCGSetPrintLevel(solver%pcg, int(solver%print_level, c_int)), &
      'HYPRE_StructPCGSetPrintLevel')
    ! logging 1: hypre keeps the initial residual, so an exact initial guess reports 0 residual
    call hypre_check(HYPRE_StructPCGSetLogging(solver%pcg, 1_c_int), 'HYPRE_StructPCGSetLogging')
    call hypre_check(HYPRE_StructPCGSetPrecond(solver%pcg, c_funloc(HYPRE_StructPFMGSolve), &
      c_funloc(HYPRE_StructPFMGSetup), solver%pfmg), 'HYPRE_StructPCGSetPrecond')
    call hypre_check(HYPRE_StructPCGSetup(solver%pcg, solver%matrix, solver%b, solver%x), &
      'HYPRE_StructPCGSetup')
    solver%setup_done = .true.
    solver%operator_changed = .false.
    solver%uses = 0
    solver%setup_iterations = 0
    solver%setups = solver%setups + 1
  end subroutine setup_krylov

  !> Direct solve on the line (`solver_line`): x = A^{-1} rhs in the owned cells and the true
  !! relative residual.
  subroutine solve_line(solver, grid, rhs, x, relative_residual)
    type(struct_solver_t), intent(inout) :: solver  !< factorised direct solver
    type(grid_t), intent(in) :: grid                !< block geometry
    real(wp), intent(in) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)  !< right-hand side
    real(wp), intent(inout) :: x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< solution out
    real(wp), intent(out) :: relative_residual     !< ||b - A x||_2 / ||b||_2
    call pack_owned(grid, rhs, solver%vector_values)
    call line_solve(solver%line, solver%vector_values, solver%tolerance, relative_residual)
    call unpack_owned(grid, solver%line%x, x)
  end subroutine solve_line

  !> Destroy PCG and PFMG if they exist.
  subroutine destroy_krylov(solver)
    type(struct_solver_t), intent(inout) :: solver  !< solver
    if (c_associated(solver%pcg)) call hypre_check(HYPRE_StructPCGDestroy(solver%pcg), &
      'HYPRE_StructPCGDestroy')
    if (c_associated(solver%pfmg)) call hypre_check(HYPRE_StructPFMGDestroy(solver%pfmg), &
      'HYPRE_StructPFMGDestroy')
    solver%pcg = c_null_ptr
    solver%pfmg = c_null_ptr
    solver%setup_done = .false.
  end subroutine destroy_krylov

  !> Abort unless the solver is initialised for this block (and has an operator, if asked).
  subroutine check_ready(solver, grid, caller, need_operator)
    type(struct_solver_t), intent(in) :: solver  !< solver
    type(grid_t), intent(in) :: grid             !< block geometry
    character(len=*), intent(in) :: caller       !< calling routine (for the message)
    logical, intent(in) :: need_operator         !< the operator must have been set
    if (.not. solver%initialized) call fatal(caller // ': solver not initialised')
    if (any(grid%lo /= solver%lo) .or. any(grid%hi /= solver%hi)) then
      call fatal(caller // ': grid differs from the one given at initialisation')
    end if
    if (need_operator .and. .not. solver%operator_set) then
      call fatal(caller // ': no operator set (call struct_solver_set_operator first)')
    end if
  end subroutine check_ready

end module solver_pressure
