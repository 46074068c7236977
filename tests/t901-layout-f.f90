! t901-layout-f.f90 - the Fortran mirrors against the compiled C library: c_sizeof of
! every bind(C) type of the module, the offset of every component (c_loc differences) and every
! constant the module defines, each compared with gran_abi_query by name. The complete list is
! t901-layout-f.inc, generated from include/granary.h with the module's raw layer
! (bindings/gen_raw.py); the hand-written checks below stay as they were.
program t901_layout_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(gran_rng) :: rng
  type(gran_segtree) :: tree
  type(gran_particles) :: parts
  type(gran_run_progress) :: progress
  type(gran_run_control) :: control
  type(gran_run_result) :: result
  type(gran_srd_options) :: srd_opt ! GSRD
  type(gran_srd_obs) :: srd_obs     ! GSRD
  type(gran_dsmc_cell_options) :: cell_opt ! cell selector
  type(gran_dsmc_cluster_stats) :: cluster_st
  type(gran_dsmc_agg_options) :: agg_opt ! aggregation in the event selectors
  type(gran_dsmc_options) :: dsmc_opt ! DSMC (speed classes)
  type(gran_dsmc_stats) :: dsmc_st    ! DSMC (speed classes)
  integer(c_int64_t) :: value
  integer :: ierr

  call check('sizeof(gran_rng)', c_sizeof(rng))
  call check('sizeof(gran_segtree)', c_sizeof(tree))
  call check('sizeof(gran_particles)', c_sizeof(parts))
  call check('sizeof(gran_run_progress)', c_sizeof(progress))
  call check('sizeof(gran_run_control)', c_sizeof(control))
  call check('sizeof(gran_run_result)', c_sizeof(result))
  call check('sizeof(gran_srd_options)', c_sizeof(srd_opt))
  call check('sizeof(gran_srd_obs)', c_sizeof(srd_obs))
  call check('sizeof(gran_dsmc_cell_options)', c_sizeof(cell_opt)) ! cell selector
  call check('sizeof(gran_dsmc_cluster_stats)', c_sizeof(cluster_st))
  call check('GRAN_SELECTOR_CELL', int(GRAN_SELECTOR_CELL, c_size_t))
  call check('GRAN_PLACE_RANDOM', int(GRAN_PLACE_RANDOM, c_size_t))
  call check('GRAN_PLACE_COLLISION', int(GRAN_PLACE_COLLISION, c_size_t))
  call check('sizeof(gran_dsmc_agg_options)', c_sizeof(agg_opt)) ! aggregation in the event selectors
  call check('GRAN_FRAG_MONOMERS', int(GRAN_FRAG_MONOMERS, c_size_t))
  call check('GRAN_FRAG_BINARY', int(GRAN_FRAG_BINARY, c_size_t))
  call check('GRAN_SPEED_CLASSES_OFF', int(GRAN_SPEED_CLASSES_OFF, c_size_t))
  call check('GRAN_SPEED_CLASSES_ON', int(GRAN_SPEED_CLASSES_ON, c_size_t))
  call check('GRAN_SPEED_CLASSES_AUTO', int(GRAN_SPEED_CLASSES_AUTO, c_size_t))
  call check('sizeof(gran_dsmc_options)', c_sizeof(dsmc_opt)) ! DSMC (speed classes)
  call check('sizeof(gran_dsmc_stats)', c_sizeof(dsmc_st))    ! DSMC (speed classes)

  call check('GRAN_VERSION_MAJOR', int(GRAN_VERSION_MAJOR, c_size_t))
  call check('GRAN_VERSION_MINOR', int(GRAN_VERSION_MINOR, c_size_t))
  call check('GRAN_VERSION_PATCH', int(GRAN_VERSION_PATCH, c_size_t))

  call check('GRAN_SUCCESS', int(GRAN_SUCCESS, c_size_t))
  call check('GRAN_ERR_ARG', int(GRAN_ERR_ARG, c_size_t))
  call check('GRAN_ERR_NOMEM', int(GRAN_ERR_NOMEM, c_size_t))
  call check('GRAN_ERR_DOMAIN', int(GRAN_ERR_DOMAIN, c_size_t))
  call check('GRAN_ERR_NOCONV', int(GRAN_ERR_NOCONV, c_size_t))
  call check('GRAN_ERR_IO', int(GRAN_ERR_IO, c_size_t))
  call check('GRAN_ERR_PARSE', int(GRAN_ERR_PARSE, c_size_t))
  call check('GRAN_ERR_UNSUPPORTED', int(GRAN_ERR_UNSUPPORTED, c_size_t))
  call check('GRAN_ERR_STATE', int(GRAN_ERR_STATE, c_size_t))
  call check('GRAN_ERR_EMPTY', int(GRAN_ERR_EMPTY, c_size_t))
  call check('GRAN_ERR_RANGE', int(GRAN_ERR_RANGE, c_size_t))
  call check('GRAN_ERR_CUDA', int(GRAN_ERR_CUDA, c_size_t))
  call check('GRAN_ERR_NUMERIC', int(GRAN_ERR_NUMERIC, c_size_t))
  call check('GRAN_ERR_INTERNAL', int(GRAN_ERR_INTERNAL, c_size_t))

  call check('GRAN_PARTICLES_DISPLACEMENT', int(GRAN_PARTICLES_DISPLACEMENT, c_size_t))
  call check('GRAN_PARTICLES_POSITION', int(GRAN_PARTICLES_POSITION, c_size_t))
  call check('GRAN_PARTICLES_MASS', int(GRAN_PARTICLES_MASS, c_size_t))

  ! GSRD devices (CUDA backend)
  call check('GRAN_SRD_DEVICE_CPU', int(GRAN_SRD_DEVICE_CPU, c_size_t))
  call check('GRAN_SRD_DEVICE_CUDA', int(GRAN_SRD_DEVICE_CUDA, c_size_t))
  call check('GRAN_SRD_DEVICE_AUTO', int(GRAN_SRD_DEVICE_AUTO, c_size_t))
  call check('GRAN_SRD_DEVICE_REFERENCE', int(GRAN_SRD_DEVICE_REFERENCE, c_size_t))

  ! every struct, field and constant of the header (generated list)
  call check_all_generated()

  ! an unknown name is an error, not a value
  call gran_abi_query('sizeof(gran_nothing)', value, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'unknown name gives GRAN_ERR_ARG')
  call expect(index(gran_last_error_message(), 'gran_nothing') > 0, 'the message names the unknown name')
  call gran_abi_query('offsetof(gran_rng, nothing)', value, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'unknown field gives GRAN_ERR_ARG')

  call test_finish('t901-layout-f')

contains

  include 't901-layout-f.inc'

  ! byte offset of a component from the start of its struct
  integer(c_size_t) function offset(field, struct)
    type(c_ptr), intent(in) :: field, struct
    offset = int(transfer(field, 0_c_intptr_t) - transfer(struct, 0_c_intptr_t), c_size_t)
  end function offset

  ! signed comparison: c_size_t holds negative error codes as their two's complement bits
  subroutine check(name, fortran_value)
    character(len=*), intent(in) :: name
    integer(c_size_t), intent(in) :: fortran_value
    integer(c_int64_t) :: c_value
    integer :: status
    character(len=64) :: values
    c_value = -huge(c_value)
    call gran_abi_query(name, c_value, status)
    if (status /= GRAN_SUCCESS) then
      call expect(.false., 'gran_abi_query knows ' // name)
    else
      write(values, '(a, i0, a, i0)') ': C ', c_value, ', Fortran ', fortran_value
      call expect(c_value == int(fortran_value, c_int64_t), name // trim(values))
    end if
  end subroutine check

end program t901_layout_f
