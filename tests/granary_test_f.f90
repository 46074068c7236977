! granary_test_f.f90 - the checks the Fortran tests share (module granary_test_f), as
! tests/granary_test.h is for the C tests. Every check prints one line, "ok: WHAT" or
! "FAILED: WHAT".
!   call expect(ok, what)    a failed check is counted and the test goes on
!   call require(ok, what)   a failed check stops the test at once (error stop 1): for a check
!                            whose failure leaves nothing to test further
!   call test_finish(name)   at the end: error stop 1 when any check failed, else one summary line
!   test_failures()          the failed checks so far
! A program that counted a failure and ends without test_finish (a stop, a return from the main
! program) still exits with status 1: the first check registers an exit handler that says so.
module granary_test_f
  use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc
  use, intrinsic :: iso_fortran_env, only: output_unit
  implicit none
  private
  public :: expect, require, test_finish, test_failures

  integer, save :: nchecks = 0, nfailed = 0
  logical, save :: finished = .false., handler = .false.

  interface
    function c_atexit(f) bind(C, name='atexit') result(rc)
      import :: c_int, c_funptr
      type(c_funptr), value :: f
      integer(c_int) :: rc
    end function c_atexit
    subroutine c_exit_now(status) bind(C, name='_exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit_now
  end interface

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (.not. handler) then
      handler = .true.
      if (c_atexit(c_funloc(exit_check)) /= 0) then
        print '(a)', 'FAILED: atexit (the test could not guard its exit status)'
        error stop 1
      end if
    end if
    nchecks = nchecks + 1
    if (ok) then
      print '(a)', 'ok: ' // what
    else
      print '(a)', 'FAILED: ' // what
      nfailed = nfailed + 1
    end if
    flush(output_unit) ! every line reaches the log, even if an exit handler ends the process
  end subroutine expect

  subroutine require(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    call expect(ok, what)
    if (.not. ok) then
      finished = .true.
      error stop 1
    end if
  end subroutine require

  subroutine test_finish(name)
    character(len=*), intent(in) :: name
    finished = .true.
    if (nfailed > 0) then
      print '(a, a, i0, a, i0, a)', name, ': ', nfailed, ' of ', nchecks, ' checks failed'
      flush(output_unit)
      error stop 1
    end if
    print '(a, a, i0, a)', name, ': all ', nchecks, ' checks passed'
  end subroutine test_finish

  integer function test_failures()
    test_failures = nfailed
  end function test_failures

  ! exit handler: failures counted but the program ended without test_finish
  subroutine exit_check() bind(C)
    if (finished .or. nfailed == 0) return
    print '(i0, a)', nfailed, ' checks failed (the test ended without test_finish)'
    flush(output_unit)
    call c_exit_now(1_c_int)
  end subroutine exit_check

end module granary_test_f
