! t890-srd-device-f.f90 - GSRD devices from Fortran: options%device and options%precision, the
! GRAN_SRD_DEVICE_* constants, gran_srd_set_device / gran_srd_get_device. A run on the host reference
! of the device algorithm follows the CPU engine to rounding (particles within 1e-9, energy ledger
! within 1e-9); moved back to the CPU it continues there; bad devices give GRAN_ERR_ARG, "cuda"
! without a GPU GRAN_ERR_UNSUPPORTED and leaves the run where it was.
program t890_srd_device_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: cpu, ref
  type(gran_srd_options) :: opt
  type(gran_srd_obs) :: oc, orf
  real(c_double), pointer :: x(:), y(:), z(:), vx(:), vy(:), vz(:)
  real(c_double), pointer :: x2(:), y2(:), z2(:), vx2(:), vy2(:), vz2(:)
  integer :: ierr, dev, ngpu, compiled

  call gran_srd_options_default(opt)
  call expect(opt%device == GRAN_SRD_DEVICE_CPU .and. opt%precision == 0, 'default device: the CPU engine')
  opt%cells = 6
  opt%eps = 0.9_c_double
  opt%sigma = 0.5_c_double
  opt%dt = 0.2_c_double
  opt%seed = 77_c_int64_t
  opt%sort_every = 5
  call gran_srd_create(opt, cpu)
  opt%device = GRAN_SRD_DEVICE_REFERENCE
  call gran_srd_create(opt, ref)
  call gran_srd_get_device(ref, dev)
  call expect(dev == GRAN_SRD_DEVICE_REFERENCE, 'get_device: reference')
  call gran_srd_advance(cpu, 12_c_int64_t)
  call gran_srd_advance(ref, 12_c_int64_t)
  call gran_srd_particles(cpu, x, y, z, vx, vy, vz)
  call gran_srd_particles(ref, x2, y2, z2, vx2, vy2, vz2)
  call expect(maxval(abs(x - x2)) < 1e-9_c_double .and. maxval(abs(vz - vz2)) < 1e-9_c_double, &
              'reference follows the CPU engine')
  call gran_srd_observe(cpu, oc)
  call gran_srd_observe(ref, orf)
  call expect(abs(oc%e_collisions - orf%e_collisions) < 1e-9_c_double * oc%e_initial, 'same dissipation')
  call expect(abs(orf%ledger_error) < 1e-12_c_double, 'ledger closed on the reference')

  ! back to the CPU: continues in step
  call gran_srd_set_device(ref, GRAN_SRD_DEVICE_CPU)
  call gran_srd_get_device(ref, dev)
  call expect(dev == GRAN_SRD_DEVICE_CPU, 'moved to the CPU')
  call gran_srd_advance(cpu, 6_c_int64_t)
  call gran_srd_advance(ref, 6_c_int64_t)
  call gran_srd_particles(cpu, x, y, z, vx, vy, vz)
  call gran_srd_particles(ref, x2, y2, z2, vx2, vy2, vz2)
  call expect(maxval(abs(vx - vx2)) < 1e-9_c_double, 'continues on the CPU')

  ! errors
  call gran_srd_set_device(ref, 7, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'device 7: GRAN_ERR_ARG')
  call expect(index(gran_last_error_message(), 'device') > 0, 'the message names the option')
  call gran_cuda_compiled(compiled)
  call gran_cuda_device_count(ngpu)
  call gran_srd_set_device(ref, GRAN_SRD_DEVICE_CUDA, ierr)
  if (compiled /= 0 .and. ngpu > 0) then
    call expect(ierr == GRAN_SUCCESS, 'cuda with a GPU')
  else
    call expect(ierr == GRAN_ERR_UNSUPPORTED, 'cuda without a GPU: GRAN_ERR_UNSUPPORTED')
    call gran_srd_get_device(ref, dev)
    call expect(dev == GRAN_SRD_DEVICE_CPU, 'a failed move leaves the run on the CPU')
  end if
  opt%device = 5
  call gran_srd_destroy(ref)
  call gran_srd_create(opt, ref, ierr)
  call expect(ierr == GRAN_ERR_ARG .and. .not. c_associated(ref), 'create with device 5: GRAN_ERR_ARG')
  call gran_srd_destroy(cpu)

  call test_finish('t890-srd-device-f')
end program t890_srd_device_f
