! t301-particles-f.f90 - Fortran twin of t301-particles: add, pointer views, swap_remove (1-based),
! growth, memory per particle, optional arrays, errors.
program t301_particles_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(gran_particles) :: p
  real(c_double), pointer :: v(:,:), r(:,:), t_last(:), x(:,:), mass(:)
  integer(c_int32_t), pointer :: species(:)
  integer(c_int64_t) :: bytes
  integer :: i, idx, ierr

  call gran_particles_init(p, 4, GRAN_PARTICLES_DISPLACEMENT)
  call gran_particles_memory(p, bytes)
  call require(bytes == 4 * 60, '60 bytes per particle with displacements')
  do i = 1, 100
    call gran_particles_add(p, [real(i, c_double), -real(i, c_double), 0.5d0 * i], mod(i, 3), idx)
    call require(idx == i, 'add returns the 1-based slot')
    r => gran_particles_view_r(p)
    t_last => gran_particles_view_t_last(p)
    r(:, idx) = [10d0 * i, 0d0, 0d0]
    t_last(idx) = 0.25d0 * i
  end do
  call require(p%n == 100 .and. p%capacity >= 100, 'n = 100 after growth')
  v => gran_particles_view_v(p)
  species => gran_particles_view_species(p)
  r => gran_particles_view_r(p)
  t_last => gran_particles_view_t_last(p)
  call require(all(shape(v) == [3, 100]) .and. size(species) == 100, 'views have n particles')
  call require(v(1, 77) == 77d0 .and. v(2, 77) == -77d0 .and. species(77) == mod(77, 3), 'growth keeps contents')
  call require(r(1, 77) == 770d0 .and. t_last(77) == 0.25d0 * 77, 'growth keeps optional arrays')
  x => gran_particles_view_x(p)
  mass => gran_particles_view_mass(p)
  call require(.not. associated(x) .and. .not. associated(mass), 'arrays without their flag are not allocated')

  call gran_particles_swap_remove(p, 1)   ! particle 100 moves into slot 1
  v => gran_particles_view_v(p)
  species => gran_particles_view_species(p)
  r => gran_particles_view_r(p)
  t_last => gran_particles_view_t_last(p)
  call require(p%n == 99 .and. v(1, 1) == 100d0 .and. species(1) == mod(100, 3), 'swap_remove moves the last particle')
  call require(r(1, 1) == 1000d0 .and. t_last(1) == 25d0, 'swap_remove moves the optional arrays')

  call gran_particles_reserve(p, 1000)
  call gran_particles_memory(p, bytes)
  call require(p%capacity == 1000 .and. bytes == 1000 * 60, 'reserve and memory')
  call gran_particles_free(p)
  call require(p%n == 0 .and. p%capacity == 0 .and. .not. c_associated(p%v), 'free zeroes the struct')

  call gran_particles_init(p, 10, 0)
  call gran_particles_memory(p, bytes)
  call require(bytes == 10 * 28, '28 bytes per particle without options')
  call gran_particles_add(p, [1d0, 2d0, 3d0], -1, ierr=ierr)
  call require(ierr == GRAN_ERR_ARG, 'negative species gives GRAN_ERR_ARG')
  call gran_particles_swap_remove(p, 1, ierr)
  call require(ierr == GRAN_ERR_RANGE, 'removing from an empty set gives GRAN_ERR_RANGE')
  call gran_particles_free(p)
  call gran_particles_init(p, -1, 0, ierr)
  call require(ierr == GRAN_ERR_ARG, 'negative capacity gives GRAN_ERR_ARG')
  call gran_particles_init(p, 1, 64, ierr)
  call require(ierr == GRAN_ERR_ARG, 'unknown flag gives GRAN_ERR_ARG')
  call test_finish('t301-particles-f')
end program t301_particles_f
