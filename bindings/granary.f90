! granary.f90 - Fortran 2003 module mirroring include/granary.h with bind(C).
!
! Two layers (SUNDIALS / libxc style): private raw interfaces `c_gran_*` that match the C
! prototypes one to one, and public wrappers `gran_*` with idiomatic arguments whose status is
! returned through an optional trailing `ierr` (when absent, a failure stops the program with the
! library's message). Plain structs (gran_rng, gran_segtree, gran_particles) are mirrored as
! bind(C) derived types; opaque handles are type(c_ptr).
module granary
  use, intrinsic :: iso_c_binding
  implicit none
  private

  ! ---- version ---------------------------------------------------------------------------------
  integer(c_int), parameter, public :: GRAN_VERSION_MAJOR = 0
  integer(c_int), parameter, public :: GRAN_VERSION_MINOR = 1
  integer(c_int), parameter, public :: GRAN_VERSION_PATCH = 0

  ! ---- error codes (same values as GRAN_ERROR_LIST) ------------------------------------------
  integer(c_int), parameter, public :: GRAN_SUCCESS = 0
  integer(c_int), parameter, public :: GRAN_ERR_ARG = -1
  integer(c_int), parameter, public :: GRAN_ERR_NOMEM = -2
  integer(c_int), parameter, public :: GRAN_ERR_DOMAIN = -3
  integer(c_int), parameter, public :: GRAN_ERR_NOCONV = -4
  integer(c_int), parameter, public :: GRAN_ERR_IO = -5
  integer(c_int), parameter, public :: GRAN_ERR_PARSE = -6
  integer(c_int), parameter, public :: GRAN_ERR_UNSUPPORTED = -7
  integer(c_int), parameter, public :: GRAN_ERR_STATE = -8
  integer(c_int), parameter, public :: GRAN_ERR_EMPTY = -9
  integer(c_int), parameter, public :: GRAN_ERR_RANGE = -10
  integer(c_int), parameter, public :: GRAN_ERR_CUDA = -11
  integer(c_int), parameter, public :: GRAN_ERR_NUMERIC = -12
  integer(c_int), parameter, public :: GRAN_ERR_INTERNAL = -99

  ! ---- particle flags --------------------------------------------------------------------------
  integer(c_int), parameter, public :: GRAN_PARTICLES_DISPLACEMENT = 1
  integer(c_int), parameter, public :: GRAN_PARTICLES_POSITION = 2
  integer(c_int), parameter, public :: GRAN_PARTICLES_MASS = 4

  ! ---- mirrored structs ------------------------------------------------------------------------
  type, bind(C), public :: gran_rng
    integer(c_int64_t) :: s(4)   ! uint64_t in C: bit patterns are identical
  end type gran_rng

  type, bind(C), public :: gran_segtree
    integer(c_int64_t) :: m
    integer(c_int64_t) :: base
    integer(c_int64_t) :: nupdate
    type(c_ptr) :: node = c_null_ptr
  end type gran_segtree

  type, bind(C), public :: gran_particles
    integer(c_int64_t) :: n = 0
    integer(c_int64_t) :: capacity = 0
    integer(c_int32_t) :: flags = 0
    integer(c_int32_t) :: pad_ = 0
    type(c_ptr) :: v = c_null_ptr
    type(c_ptr) :: species = c_null_ptr
    type(c_ptr) :: r = c_null_ptr
    type(c_ptr) :: t_last = c_null_ptr
    type(c_ptr) :: x = c_null_ptr
    type(c_ptr) :: mass = c_null_ptr
  end type gran_particles

  public :: gran_get_version, gran_strerror, gran_last_error_message, gran_check

  ! @@SECTION core-public@@ (rng, segtree, particles: names made public here)
  ! @@END core-public@@
  ! @@SECTION theory-public@@
  ! @@END theory-public@@
  ! @@SECTION dsmc-public@@
  ! @@END dsmc-public@@
  ! @@SECTION analysis-public@@
  ! @@END analysis-public@@
  ! @@SECTION io-public@@
  ! @@END io-public@@

  ! ---- raw C interfaces ------------------------------------------------------------------------
  interface
    function c_gran_get_version(major, minor, patch) bind(C, name='gran_get_version') result(ierr)
      import :: c_int
      integer(c_int), intent(out) :: major, minor, patch
      integer(c_int) :: ierr
    end function c_gran_get_version
    function c_gran_strerror(code) bind(C, name='gran_strerror') result(p)
      import :: c_int, c_ptr
      integer(c_int), value :: code
      type(c_ptr) :: p
    end function c_gran_strerror
    function c_gran_last_error_copy(buf, len) bind(C, name='gran_last_error_copy') result(ierr)
      import :: c_int, c_int64_t, c_char
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int64_t), value :: len
      integer(c_int) :: ierr
    end function c_gran_last_error_copy
    function c_strlen(s) bind(C, name='strlen') result(n)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: n
    end function c_strlen
    ! @@SECTION core-interfaces@@
    ! @@END core-interfaces@@
    ! @@SECTION theory-interfaces@@
    ! @@END theory-interfaces@@
    ! @@SECTION dsmc-interfaces@@
    ! @@END dsmc-interfaces@@
    ! @@SECTION analysis-interfaces@@
    ! @@END analysis-interfaces@@
    ! @@SECTION io-interfaces@@
    ! @@END io-interfaces@@
  end interface

contains

  !> Version of the linked library.
  subroutine gran_get_version(major, minor, patch, ierr)
    integer, intent(out) :: major, minor, patch
    integer, intent(out), optional :: ierr
    integer(c_int) :: a, b, c
    call gran_check(c_gran_get_version(a, b, c), ierr)
    major = a; minor = b; patch = c
  end subroutine gran_get_version

  !> Name and description of an error code.
  function gran_strerror(code) result(msg)
    integer, intent(in) :: code
    character(len=:), allocatable :: msg
    type(c_ptr) :: p
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    p = c_gran_strerror(int(code, c_int))
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = chars(i)
    end do
  end function gran_strerror

  !> Message of the last failure in this thread.
  function gran_last_error_message() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(1024)
    integer :: i, n
    buf = c_null_char
    if (c_gran_last_error_copy(buf, int(size(buf), c_int64_t)) /= 0) buf(1) = c_null_char
    n = 0
    do while (n < size(buf))
      if (buf(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = buf(i)
    end do
  end function gran_last_error_message

  !> Hand a C status to the optional ierr; without ierr, stop with the message on failure.
  subroutine gran_check(status, ierr)
    integer(c_int), intent(in) :: status
    integer, intent(out), optional :: ierr
    if (present(ierr)) then
      ierr = int(status)
    else if (status /= GRAN_SUCCESS) then
      write(*, '(a)') 'granary: ' // gran_strerror(int(status)) // ': ' // gran_last_error_message()
      error stop 1
    end if
  end subroutine gran_check

  ! @@SECTION core-procedures@@
  ! @@END core-procedures@@
  ! @@SECTION theory-procedures@@
  ! @@END theory-procedures@@
  ! @@SECTION dsmc-procedures@@
  ! @@END dsmc-procedures@@
  ! @@SECTION analysis-procedures@@
  ! @@END analysis-procedures@@
  ! @@SECTION io-procedures@@
  ! @@END io-procedures@@
end module granary
