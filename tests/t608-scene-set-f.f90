! t608-scene-set-f.f90 - gran_scene_set from Fortran (an override lands in the scene and its text;
! a bad one fails with GRAN_ERR_PARSE naming the key), and the wrappers' own array checks: with
! ierr, gran_last_error_message() names the array and its sizes; without, the program stops with
! that message on stderr (not stdout).
program t608_scene_set_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: scene, mix
  integer :: ierr, m, nt, nl, u, st
  real(c_double) :: t0, t1, small(2), mass(1)
  character(len=:), allocatable :: text, msg
  character(len=1), parameter :: nl_ = achar(10)
  character(len=512) :: self, arg, line, errf, outf
  character(len=64) :: tag
  logical :: in_out, in_err
  real :: r

  text = '[mixture]' // nl_ // 'nspecies = 2' // nl_ // 'mass = [1.0, 2.0]' // nl_ // &
         'density = [0.1, 0.05]' // nl_ // '[engine]' // nl_ // 'counts = [500, 250]' // nl_ // &
         'seed = 5' // nl_ // 't_end = 4.0' // nl_ // '[observables]' // nl_ // &
         'times = [0.5, 1.0, 2.0, 4.0]' // nl_ // '[output]' // nl_ // 'path = "never.h5"' // nl_
  call gran_scene_parse(text, 'f.toml', scene)

  ! the child: a wrong array size without ierr stops the program (message on stderr)
  call get_command_argument(1, arg)
  if (trim(arg) == 'die') then
    call gran_scene_times(scene, small)
    print '(a)', 'not reached'
    stop
  end if

  call gran_scene_set(scene, 'engine.seed', '7')
  call gran_scene_set(scene, 'observables.times', '[1.0, 2.0]')
  call gran_scene_sizes(scene, m, nt, nl, t0, t1)
  call require(nt == 2, 'gran_scene_set: observables.times has 2 output times')
  call gran_scene_text(scene, msg)
  call require(index(msg, 'seed = 7') > 0, 'the scene text has the override: ' // msg)
  call gran_scene_set(scene, 'engine.seed', '"seven"', ierr)
  call require(ierr == GRAN_ERR_PARSE, 'a string for engine.seed: GRAN_ERR_PARSE')
  msg = gran_last_error_message()
  call require(index(msg, 'engine.seed') > 0, 'the message names the key: ' // msg)
  call gran_scene_set(scene, 'engine.nosuch', '1', ierr)
  msg = gran_last_error_message()
  call require(ierr == GRAN_ERR_PARSE .and. index(msg, 'engine.nosuch') > 0, 'an unknown key: GRAN_ERR_PARSE naming it: ' // msg)

  ! array checks of the wrappers: the message names the array and the sizes
  call gran_clear_error()
  call gran_scene_set(scene, 'observables.times', '[1.0, 2.0, 3.0]')
  call gran_scene_times(scene, small, ierr)
  msg = gran_last_error_message()
  call require(ierr == GRAN_ERR_ARG, 'gran_scene_times with 2 of 3 elements: GRAN_ERR_ARG')
  call require(index(msg, 'gran_scene_times') > 0 .and. index(msg, 'times has 2 elements, expected 3') > 0, &
               'the message names the array and its sizes: "' // msg // '"')
  call gran_scene_mixture(scene, mix)
  call gran_mixture_get(mix, mass=mass, ierr=ierr)
  msg = gran_last_error_message()
  call require(ierr == GRAN_ERR_ARG .and. index(msg, 'size(mass)') > 0 .and. index(msg, '1 elements, expected 2') > 0, &
               'gran_mixture_get with mass(1) of 2 species: "' // msg // '"')
  call gran_mixture_destroy(mix)
  call gran_set_error_message(GRAN_ERR_RANGE, 'from Fortran', ierr)
  msg = gran_last_error_message()
  call require(ierr == GRAN_ERR_RANGE .and. msg == 'from Fortran', &
               'gran_set_error_message sets the message and returns the code')
  call gran_set_error_message(0, 'not an error', ierr)
  msg = gran_last_error_message()
  call require(ierr == GRAN_ERR_ARG .and. index(msg, 'code') > 0, &
               'gran_set_error_message refuses a code that is not an error')

  ! without ierr: the child stops; the message is on stderr, nothing of it on stdout
  call random_seed()
  call random_number(r)
  write(tag, '(i0)') int(r * 1.0e9)
  errf = '/tmp/granary-t608f-' // trim(tag) // '.err'
  outf = '/tmp/granary-t608f-' // trim(tag) // '.out'
  call get_command_argument(0, self)
  call execute_command_line(trim(self) // ' die > ' // trim(outf) // ' 2> ' // trim(errf), exitstat=st)
  call require(st /= 0, 'the child stopped with a nonzero status')
  in_out = .false.
  in_err = .false.
  open(newunit=u, file=trim(outf), status='old', action='read')
  do
    read(u, '(a)', iostat=ierr) line
    if (ierr /= 0) exit
    if (index(line, 'times has 2 elements') > 0) in_out = .true.
  end do
  close(u, status='delete')
  open(newunit=u, file=trim(errf), status='old', action='read')
  do
    read(u, '(a)', iostat=ierr) line
    if (ierr /= 0) exit
    if (index(line, 'granary: GRAN_ERR_ARG') > 0 .and. index(line, 'times has 2 elements, expected 4') > 0) in_err = .true.
  end do
  close(u, status='delete')
  call expect(in_err .and. .not. in_out, 'without ierr the message goes to stderr, not stdout')

  call gran_scene_destroy(scene)
  deallocate(text, msg) ! a main program's allocatables are not freed at its end (LeakSanitizer)
  call test_finish('t608-scene-set-f')
end program t608_scene_set_f
