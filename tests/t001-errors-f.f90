! t001-errors-f.f90 - Fortran twin of t001: version, build configuration, status codes and
! messages, warnings and the CUDA queries through the module.
program t001_errors_f
  use granary
  use granary_test_f
  use, intrinsic :: iso_c_binding
  implicit none
  integer :: major, minor, patch, ierr, compiled, ngpu
  integer(c_int64_t) :: nwarn
  type(c_ptr) :: mix
  character(len=:), allocatable :: cfg, loc

  call gran_get_version(major, minor, patch)
  call require(major == GRAN_VERSION_MAJOR .and. minor == GRAN_VERSION_MINOR .and. &
               patch == GRAN_VERSION_PATCH, 'version matches the module parameters')
  cfg = gran_get_build_config()
  call require(index(cfg, 'cuda=') > 0, 'build configuration names the CUDA setting: ' // cfg)
  call require(index(gran_strerror(GRAN_ERR_ARG), 'GRAN_ERR_ARG') == 1, 'strerror names GRAN_ERR_ARG')
  call require(index(gran_strerror(12345), 'unknown') > 0, 'strerror of an unknown code')

  ! a failing call hands its status to ierr and leaves a message naming the argument
  call gran_mixture_create(mix, density=[0.1d0, -1d0], ierr=ierr)
  call require(ierr == GRAN_ERR_ARG, 'negative density gives GRAN_ERR_ARG')
  call require(index(gran_last_error_message(), 'density') > 0, &
               'message names density: ' // gran_last_error_message())
  call require(index(gran_last_error_message(), '.cpp') == 0, 'message carries no source location')
  loc = gran_last_error_location()
  call require(index(loc, '.cpp:') > 0 .and. index(loc, 'GRAN_ERR_ARG') > 0, &
               'location names the source line and the code: ' // loc)
  call gran_clear_error()
  call require(len(gran_last_error_message()) == 0, 'clear_error empties the message')
  call require(len(gran_last_error_location()) == 0, 'clear_error empties the location')

  call gran_warning_count(nwarn)
  call require(nwarn >= 0, 'warning count is readable')
  call require(len(gran_last_warning()) >= 0, 'last warning is readable')

  call gran_cuda_compiled(compiled)
  call require(compiled == 0 .or. compiled == 1, 'cuda_compiled is 0 or 1')
  call gran_cuda_device_count(ngpu)
  call require(ngpu >= 0, 'device count is not negative')
  deallocate(cfg, loc) ! main-program variables are never freed automatically (LeakSanitizer)
  call test_finish('t001-errors-f')
end program t001_errors_f
