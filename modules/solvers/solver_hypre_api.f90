!> Raw ISO_C_BINDING interfaces to the part of the hypre C API that MPMICE uses: Struct grids,
!! stencils, matrices and vectors, the Struct PCG solver and the PFMG multigrid preconditioner.
!!
!! This is the only module that declares hypre entry points; `solver_pressure` is the only one
!! that calls them. Conventions of the bindings (hypre 2.26 built with 32-bit `HYPRE_Int` and
!! double `HYPRE_Real`/`HYPRE_Complex`, see `HYPRE_config.h`):
!! * every hypre object handle (`HYPRE_StructGrid`, `HYPRE_StructSolver`, ...) is a C pointer and
!!   is declared `type(c_ptr)`; it is passed by value, except where hypre returns a new handle
!!   through a pointer argument (the `*Create` calls), where it is passed by reference;
!! * `HYPRE_Int` is `integer(c_int)`, `HYPRE_Real` and `HYPRE_Complex` are `real(c_double)`;
!! * every function returns hypre's error flag (`integer(c_int)`, 0 on success). The flag is
!!   global and sticky inside hypre: callers check it after each call (`hypre_check`) and clear
!!   the bits they accept (`HYPRE_ClearError`);
!! * hypre takes a C `MPI_Comm`: `hypre_c_comm` gets it from `parallel_comm%c_comm_handle`
!!   (MPI calls stay in parallel/).
module solver_hypre_api
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_funptr, c_char, c_null_char
  use parallel_comm, only: MPI_Comm, c_comm_handle
  use mpmice_errors, only: fatal
  use mpmice_kinds, only: msg_len
  implicit none
  private

  public :: hypre_c_comm, hypre_check, hypre_error_text
  public :: HYPRE_ERROR_GENERIC, HYPRE_ERROR_MEMORY, HYPRE_ERROR_ARG, HYPRE_ERROR_CONV
  public :: HYPRE_Init, HYPRE_GetError, HYPRE_ClearError, HYPRE_ClearAllErrors
  public :: HYPRE_StructGridCreate, HYPRE_StructGridDestroy, HYPRE_StructGridSetExtents, &
    HYPRE_StructGridSetPeriodic, HYPRE_StructGridAssemble
  public :: HYPRE_StructStencilCreate, HYPRE_StructStencilDestroy, HYPRE_StructStencilSetElement
  public :: HYPRE_StructMatrixCreate, HYPRE_StructMatrixDestroy, HYPRE_StructMatrixSetSymmetric, &
    HYPRE_StructMatrixInitialize, HYPRE_StructMatrixSetBoxValues, HYPRE_StructMatrixAssemble
  public :: HYPRE_StructVectorCreate, HYPRE_StructVectorDestroy, HYPRE_StructVectorInitialize, &
    HYPRE_StructVectorSetBoxValues, HYPRE_StructVectorGetBoxValues, HYPRE_StructVectorAssemble
  public :: HYPRE_StructPCGCreate, HYPRE_StructPCGDestroy, HYPRE_StructPCGSetTol, &
    HYPRE_StructPCGSetMaxIter, HYPRE_StructPCGSetTwoNorm, HYPRE_StructPCGSetRelChange, &
    HYPRE_StructPCGSetPrintLevel, HYPRE_StructPCGSetLogging, HYPRE_StructPCGSetPrecond, &
    HYPRE_StructPCGSetup, HYPRE_StructPCGSolve, HYPRE_StructPCGGetNumIterations, &
    HYPRE_StructPCGGetFinalRelativeResidualNorm
  public :: HYPRE_StructPFMGCreate, HYPRE_StructPFMGDestroy, HYPRE_StructPFMGSetMaxIter, &
    HYPRE_StructPFMGSetTol, HYPRE_StructPFMGSetZeroGuess, HYPRE_StructPFMGSetRelaxType, &
    HYPRE_StructPFMGSetRAPType, HYPRE_StructPFMGSetNumPreRelax, HYPRE_StructPFMGSetNumPostRelax, &
    HYPRE_StructPFMGSetSkipRelax, HYPRE_StructPFMGSetPrintLevel, HYPRE_StructPFMGSetLogging, &
    HYPRE_StructPFMGSetup, HYPRE_StructPFMGSolve

  !> hypre error bits (`HYPRE_utilities.h`).
  integer(c_int), parameter :: HYPRE_ERROR_GENERIC = 1_c_int   !< generic error
  integer(c_int), parameter :: HYPRE_ERROR_MEMORY = 2_c_int    !< unable to allocate memory
  integer(c_int), parameter :: HYPRE_ERROR_ARG = 4_c_int       !< argument error
  integer(c_int), parameter :: HYPRE_ERROR_CONV = 256_c_int    !< method did not converge

  interface
    ! ---------------------------------------------------------------- utilities
    function HYPRE_Init() bind(c, name='HYPRE_Init') result(ierr)
      import :: c_int
      integer(c_int) :: ierr
    end function HYPRE_Init
    function HYPRE_GetError() bind(c, name='HYPRE_GetError') result(ierr)
      import :: c_int
      integer(c_int) :: ierr
    end function HYPRE_GetError
    function HYPRE_ClearError(code) bind(c, name='HYPRE_ClearError') result(ierr)
      import :: c_int
      integer(c_int), value :: code
      integer(c_int) :: ierr
    end function HYPRE_ClearError
    function HYPRE_ClearAllErrors() bind(c, name='HYPRE_ClearAllErrors') result(ierr)
      import :: c_int
      integer(c_int) :: ierr
    end function HYPRE_ClearAllErrors
    subroutine c_hypre_describe_error(ierr, descr) bind(c, name='HYPRE_DescribeError')
      import :: c_int, c_char
      integer(c_int), value :: ierr
      character(kind=c_char), intent(out) :: descr(*)
    end subroutine c_hypre_describe_error

    ! ---------------------------------------------------------------- grid
    function HYPRE_StructGridCreate(comm, ndim, grid) bind(c, name='HYPRE_StructGridCreate') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: comm
      integer(c_int), value :: ndim
      type(c_ptr), intent(out) :: grid
      integer(c_int) :: ierr
    end function HYPRE_StructGridCreate
    function HYPRE_StructGridDestroy(grid) bind(c, name='HYPRE_StructGridDestroy') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: grid
      integer(c_int) :: ierr
    end function HYPRE_StructGridDestroy
    function HYPRE_StructGridSetExtents(grid, ilower, iupper) &
        bind(c, name='HYPRE_StructGridSetExtents') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: grid
      integer(c_int), intent(in) :: ilower(*), iupper(*)
      integer(c_int) :: ierr
    end function HYPRE_StructGridSetExtents
    function HYPRE_StructGridSetPeriodic(grid, periodic) &
        bind(c, name='HYPRE_StructGridSetPeriodic') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: grid
      integer(c_int), intent(in) :: periodic(*)
      integer(c_int) :: ierr
    end function HYPRE_StructGridSetPeriodic
    function HYPRE_StructGridAssemble(grid) bind(c, name='HYPRE_StructGridAssemble') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: grid
      integer(c_int) :: ierr
    end function HYPRE_StructGridAssemble

    ! ---------------------------------------------------------------- stencil
    function HYPRE_StructStencilCreate(ndim, size, stencil) &
        bind(c, name='HYPRE_StructStencilCreate') result(ierr)
      import :: c_int, c_ptr
      integer(c_int), value :: ndim, size
      type(c_ptr), intent(out) :: stencil
      integer(c_int) :: ierr
    end function HYPRE_StructStencilCreate
    function HYPRE_StructStencilDestroy(stencil) bind(c, name='HYPRE_StructStencilDestroy') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: stencil
      integer(c_int) :: ierr
    end function HYPRE_StructStencilDestroy
    function HYPRE_StructStencilSetElement(stencil, entry, offset) &
        bind(c, name='HYPRE_StructStencilSetElement') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: stencil
      integer(c_int), value :: entry
      integer(c_int), intent(in) :: offset(*)
      integer(c_int) :: ierr
    end function HYPRE_StructStencilSetElement

    ! ---------------------------------------------------------------- matrix
    function HYPRE_StructMatrixCreate(comm, grid, stencil, matrix) &
        bind(c, name='HYPRE_StructMatrixCreate') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: comm, grid, stencil
      type(c_ptr), intent(out) :: matrix
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixCreate
    function HYPRE_StructMatrixDestroy(matrix) bind(c, name='HYPRE_StructMatrixDestroy') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: matrix
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixDestroy
    function HYPRE_StructMatrixSetSymmetric(matrix, symmetric) &
        bind(c, name='HYPRE_StructMatrixSetSymmetric') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: matrix
      integer(c_int), value :: symmetric
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixSetSymmetric
    function HYPRE_StructMatrixInitialize(matrix) bind(c, name='HYPRE_StructMatrixInitialize') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: matrix
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixInitialize
    function HYPRE_StructMatrixSetBoxValues(matrix, ilower, iupper, nentries, entries, values) &
        bind(c, name='HYPRE_StructMatrixSetBoxValues') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: matrix
      integer(c_int), intent(in) :: ilower(*), iupper(*)
      integer(c_int), value :: nentries
      integer(c_int), intent(in) :: entries(*)
      real(c_double), intent(in) :: values(*)
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixSetBoxValues
    function HYPRE_StructMatrixAssemble(matrix) bind(c, name='HYPRE_StructMatrixAssemble') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: matrix
      integer(c_int) :: ierr
    end function HYPRE_StructMatrixAssemble

    ! ---------------------------------------------------------------- vector
    function HYPRE_StructVectorCreate(comm, grid, vector) bind(c, name='HYPRE_StructVectorCreate') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: comm, grid
      type(c_ptr), intent(out) :: vector
      integer(c_int) :: ierr
    end function HYPRE_StructVectorCreate
    function HYPRE_StructVectorDestroy(vector) bind(c, name='HYPRE_StructVectorDestroy') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: vector
      integer(c_int) :: ierr
    end function HYPRE_StructVectorDestroy
    function HYPRE_StructVectorInitialize(vector) bind(c, name='HYPRE_StructVectorInitialize') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: vector
      integer(c_int) :: ierr
    end function HYPRE_StructVectorInitialize
    function HYPRE_StructVectorSetBoxValues(vector, ilower, iupper, values) &
        bind(c, name='HYPRE_StructVectorSetBoxValues') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: vector
      integer(c_int), intent(in) :: ilower(*), iupper(*)
      real(c_double), intent(in) :: values(*)
      integer(c_int) :: ierr
    end function HYPRE_StructVectorSetBoxValues
    function HYPRE_StructVectorGetBoxValues(vector, ilower, iupper, values) &
        bind(c, name='HYPRE_StructVectorGetBoxValues') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: vector
      integer(c_int), intent(in) :: ilower(*), iupper(*)
      real(c_double), intent(inout) :: values(*)
      integer(c_int) :: ierr
    end function HYPRE_StructVectorGetBoxValues
    function HYPRE_StructVectorAssemble(vector) bind(c, name='HYPRE_StructVectorAssemble') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: vector
      integer(c_int) :: ierr
    end function HYPRE_StructVectorAssemble

    ! ---------------------------------------------------------------- PCG
    function HYPRE_StructPCGCreate(comm, solver) bind(c, name='HYPRE_StructPCGCreate') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: comm
      type(c_ptr), intent(out) :: solver
      integer(c_int) :: ierr
    end function HYPRE_StructPCGCreate
    function HYPRE_StructPCGDestroy(solver) bind(c, name='HYPRE_StructPCGDestroy') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int) :: ierr
    end function HYPRE_StructPCGDestroy
    function HYPRE_StructPCGSetTol(solver, tol) bind(c, name='HYPRE_StructPCGSetTol') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: solver
      real(c_double), value :: tol
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetTol
    function HYPRE_StructPCGSetMaxIter(solver, max_iter) bind(c, name='HYPRE_StructPCGSetMaxIter') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: max_iter
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetMaxIter
    function HYPRE_StructPCGSetTwoNorm(solver, two_norm) bind(c, name='HYPRE_StructPCGSetTwoNorm') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: two_norm
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetTwoNorm
    function HYPRE_StructPCGSetRelChange(solver, rel_change) &
        bind(c, name='HYPRE_StructPCGSetRelChange') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: rel_change
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetRelChange
    function HYPRE_StructPCGSetPrintLevel(solver, level) &
        bind(c, name='HYPRE_StructPCGSetPrintLevel') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: level
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetPrintLevel
    function HYPRE_StructPCGSetLogging(solver, logging) bind(c, name='HYPRE_StructPCGSetLogging') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: logging
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetLogging
    !> `precond` and `precond_setup` are `HYPRE_PtrToStructSolverFcn` function pointers, e.g.
    !! `c_funloc(HYPRE_StructPFMGSolve)` and `c_funloc(HYPRE_StructPFMGSetup)`.
    function HYPRE_StructPCGSetPrecond(solver, precond, precond_setup, precond_solver) &
        bind(c, name='HYPRE_StructPCGSetPrecond') result(ierr)
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: solver
      type(c_funptr), value :: precond, precond_setup
      type(c_ptr), value :: precond_solver
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetPrecond
    function HYPRE_StructPCGSetup(solver, a, b, x) bind(c, name='HYPRE_StructPCGSetup') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver, a, b, x
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSetup
    function HYPRE_StructPCGSolve(solver, a, b, x) bind(c, name='HYPRE_StructPCGSolve') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver, a, b, x
      integer(c_int) :: ierr
    end function HYPRE_StructPCGSolve
    function HYPRE_StructPCGGetNumIterations(solver, num_iterations) &
        bind(c, name='HYPRE_StructPCGGetNumIterations') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), intent(out) :: num_iterations
      integer(c_int) :: ierr
    end function HYPRE_StructPCGGetNumIterations
    function HYPRE_StructPCGGetFinalRelativeResidualNorm(solver, norm) &
        bind(c, name='HYPRE_StructPCGGetFinalRelativeResidualNorm') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: solver
      real(c_double), intent(out) :: norm
      integer(c_int) :: ierr
    end function HYPRE_StructPCGGetFinalRelativeResidualNorm

    ! ---------------------------------------------------------------- PFMG
    function HYPRE_StructPFMGCreate(comm, solver) bind(c, name='HYPRE_StructPFMGCreate') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: comm
      type(c_ptr), intent(out) :: solver
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGCreate
    function HYPRE_StructPFMGDestroy(solver) bind(c, name='HYPRE_StructPFMGDestroy') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGDestroy
    function HYPRE_StructPFMGSetMaxIter(solver, max_iter) &
        bind(c, name='HYPRE_StructPFMGSetMaxIter') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: max_iter
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetMaxIter
    function HYPRE_StructPFMGSetTol(solver, tol) bind(c, name='HYPRE_StructPFMGSetTol') result(ierr)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: solver
      real(c_double), value :: tol
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetTol
    function HYPRE_StructPFMGSetZeroGuess(solver) bind(c, name='HYPRE_StructPFMGSetZeroGuess') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetZeroGuess
    function HYPRE_StructPFMGSetRelaxType(solver, relax_type) &
        bind(c, name='HYPRE_StructPFMGSetRelaxType') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: relax_type
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetRelaxType
    function HYPRE_StructPFMGSetRAPType(solver, rap_type) &
        bind(c, name='HYPRE_StructPFMGSetRAPType') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: rap_type
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetRAPType
    function HYPRE_StructPFMGSetNumPreRelax(solver, num_pre_relax) &
        bind(c, name='HYPRE_StructPFMGSetNumPreRelax') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: num_pre_relax
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetNumPreRelax
    function HYPRE_StructPFMGSetNumPostRelax(solver, num_post_relax) &
        bind(c, name='HYPRE_StructPFMGSetNumPostRelax') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: num_post_relax
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetNumPostRelax
    function HYPRE_StructPFMGSetSkipRelax(solver, skip_relax) &
        bind(c, name='HYPRE_StructPFMGSetSkipRelax') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: skip_relax
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetSkipRelax
    function HYPRE_StructPFMGSetPrintLevel(solver, print_level) &
        bind(c, name='HYPRE_StructPFMGSetPrintLevel') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: print_level
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetPrintLevel
    function HYPRE_StructPFMGSetLogging(solver, logging) &
        bind(c, name='HYPRE_StructPFMGSetLogging') result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
      integer(c_int), value :: logging
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetLogging
    !> Also the `precond_setup` callback handed to `HYPRE_StructPCGSetPrecond`.
    function HYPRE_StructPFMGSetup(solver, a, b, x) bind(c, name='HYPRE_StructPFMGSetup') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver, a, b, x
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSetup
    !> Also the `precond` callback handed to `HYPRE_StructPCGSetPrecond`.
    function HYPRE_StructPFMGSolve(solver, a, b, x) bind(c, name='HYPRE_StructPFMGSolve') &
        result(ierr)
      import :: c_int, c_ptr
      type(c_ptr), value :: solver, a, b, x
      integer(c_int) :: ierr
    end function HYPRE_StructPFMGSolve
  end interface

contains

  !> The C `MPI_Comm` handle that hypre expects for an `mpi_f08` communicator.
  function hypre_c_comm(comm) result(ccomm)
    type(MPI_Comm), intent(in) :: comm  !< Fortran communicator
    type(c_ptr) :: ccomm
    ccomm = c_comm_handle(comm)
  end function hypre_c_comm

  !> hypre's description of the error bits in `ierr` (e.g. `[Argument error] `).
  function hypre_error_text(ierr) result(text)
    integer(c_int), intent(in) :: ierr  !< hypre error flag
    character(len=:), allocatable :: text
    character(kind=c_char) :: buffer(msg_len)
    integer :: n, i
    buffer = c_null_char
    call c_hypre_describe_error(ierr, buffer)
    n = 0
    do while (n < msg_len)
      if (buffer(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: text)
    do i = 1, n
      text(i:i) = buffer(i)
    end do
  end function hypre_error_text

  !> Abort (`fatal`) if a hypre call returned a non-zero error flag. `what` names the call.
  subroutine hypre_check(ierr, what)
    integer(c_int), intent(in) :: ierr   !< error flag returned by the call
    character(len=*), intent(in) :: what !< name of the hypre call (for the message)
    character(len=16) :: code
    if (ierr == 0_c_int) return
    write(code, '(i0)') ierr
    call fatal('hypre: ' // what // ' failed with error flag ' // trim(code) // ': ' &
      // hypre_error_text(ierr))
  end subroutine hypre_check
end module solver_hypre_api
