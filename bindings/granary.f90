! granary.f90 - Fortran 2003 module mirroring include/granary.h with bind(C).
!
! Two layers (SUNDIALS / libxc style): private raw interfaces `c_gran_*` that match the C
! prototypes one to one, and public wrappers `gran_*` with idiomatic arguments whose status is
! returned through an optional trailing `ierr` (when absent, a failure stops the program with the
! library's message). Plain structs (gran_rng, gran_segtree, gran_particles, the option and
! statistics structs) are mirrored as bind(C) derived types; opaque handles are type(c_ptr).
!
! The raw layer is generated: granary_raw.inc (every constant, every bind(C) type and every raw
! interface) is written by bindings/gen_raw.py from include/granary.h, and `make` fails when it is
! not current. This file holds the hand-written wrappers; docs/developers/fortran.md says how to
! add a function or a field.
module granary
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private

  ! constants, bind(C) types and the raw interfaces c_gran_*, generated from include/granary.h
  include 'granary_raw.inc'

  interface
    function c_strlen(s) bind(C, name='strlen') result(n)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: n
    end function c_strlen
  end interface

  public :: gran_get_version, gran_strerror, gran_last_error_message, gran_last_error_location, gran_check
  public :: gran_get_build_config, gran_clear_error, gran_warning_count, gran_last_warning
  public :: gran_set_error_message
  public :: gran_cuda_compiled, gran_cuda_device_count

  ! ---- foundation (rng, segtree, particles, abi) ----
  ! Indices handed across (segment-tree leaves, particle slots) are 1-based in the wrappers; values
  ! stored in arrays (species) are the library's 0-based ones. Seeds and stream ids are the bits of
  ! a uint64_t in an integer(c_int64_t). Vectors are real(c_double) :: v(3, n) (C's interleaved xyz).
  public :: gran_rng_seed, gran_rng_stream, gran_rng_jump, gran_rng_long_jump, gran_rng_u64, &
            gran_rng_uniform, gran_rng_uniform_pos, gran_rng_exponential, gran_rng_normal, &
            gran_rng_unit_vector3, gran_rng_unit_vector2, gran_cuda_rng_uniform
  public :: gran_segtree_init, gran_segtree_free, gran_segtree_set, gran_segtree_set_batch, &
            gran_segtree_get, gran_segtree_total, gran_segtree_sample, gran_segtree_rebuild
  public :: gran_particles_init, gran_particles_free, gran_particles_reserve, gran_particles_add, &
            gran_particles_swap_remove, gran_particles_memory
  ! pointer views of the particle arrays (particles in use only; stale after add/reserve)
  public :: gran_particles_view_v, gran_particles_view_species, gran_particles_view_r, &
            gran_particles_view_t_last, gran_particles_view_x, gran_particles_view_mass
  public :: gran_abi_query
  ! ---- kinetic theory ----
  ! Kinetic theory (include/granary.h, theory section). Mixtures are type(c_ptr) handles. Species
  ! indices are 1-based here (0-based in C); per-species time series are arrays (M, ntimes) and pair
  ! matrices (M, M) (symmetric, so the C row-major layout reads the same).
  public :: gran_mixture_create, gran_mixture_create_powerlaw, gran_mixture_destroy, gran_mixture_nspecies
  public :: gran_mixture_get, gran_mixture_set_restitution, gran_mixture_set_restitution_matrix
  public :: gran_mixture_set_viscoelastic, gran_mixture_set_viscoelastic_matrix
  public :: gran_mixture_set_viscoelastic_material, gran_mixture_set_g2, gran_mixture_set_g2_matrix
  public :: gran_mixture_restitution_model, gran_mixture_pair
  public :: gran_viscoelastic_eps, gran_viscoelastic_eps_vn
  public :: gran_theory_cooling_rates, gran_theory_tau_v, gran_theory_diffusion, gran_theory_collision_rate1
  public :: gran_theory_hcs, gran_theory_temperatures, gran_theory_msd_hcs, gran_theory_msd
  public :: gran_theory_temperatures_driven
  ! GRAN_THEORY_MAXWELLIAN (reference) or GRAN_THEORY_SONINE (first Sonine level, docs/physics-sonine.md)
  public :: gran_theory_hcs_approx, gran_theory_sonine_rates, gran_theory_temperatures_approx
  public :: gran_theory_hcs_sonine2, gran_theory_sonine2_rates, gran_theory_hcs_sonine_n
  public :: gran_theory_temperatures_sonine2, gran_theory_msd_sonine2
  public :: gran_theory_diffusion_approx, gran_theory_msd_hcs_approx, gran_theory_msd_approx
  public :: gran_theory_tamsd_approx, gran_theory_msd_sonine
  public :: gran_theory_tamsd, gran_theory_tamsd_sampled, gran_theory_tamsd_parts, gran_theory_msd_mono, gran_theory_reduced_time
  public :: gran_theory_tracer_gamma_approx, gran_theory_tracer_tau_v_hat
  public :: gran_theory_mean_relative_speed, gran_theory_collision_rates, gran_theory_collision_counts
  ! aggregation and fragmentation kinetics (src/theory/aggregation.cpp)
  public :: gran_theory_agg_fractions, gran_theory_aggregation, gran_theory_smoluchowski_constant
  ! ---- DSMC engines ----
  ! DSMC engine (include/granary.h, dsmc section). Engines are type(c_ptr) handles; per-species
  ! arrays have M entries, collision counts are (M, M) (symmetric), trajectories (3, nsamples, ntraj).
  ! Species offsets are 0-based particle indices as in C.
  public :: gran_dsmc_options_default, gran_dsmc_create, gran_dsmc_destroy, gran_dsmc_advance
  public :: gran_dsmc_advance_collisions, gran_dsmc_time, gran_dsmc_get_stats, gran_dsmc_counts
  public :: gran_dsmc_temperatures, gran_dsmc_msd, gran_dsmc_collision_counts, gran_dsmc_sonine_a2
  public :: gran_dsmc_energy, gran_dsmc_momentum, gran_dsmc_particles, gran_dsmc_species_offsets
  public :: gran_dsmc_species_velocities
  public :: gran_dsmc_trajectories, gran_dsmc_checkpoint_write, gran_dsmc_checkpoint_read
  ! ---- time-step/cell DSMC, aggregation, fragmentation, thermostat (src/dsmc/cell.cpp) ----
  public :: gran_dsmc_cell_options_default, gran_dsmc_create_cell, gran_dsmc_cell_info, gran_scene_dsmc_cell_options
  public :: gran_dsmc_get_cluster_stats, gran_dsmc_size_distribution
  ! ---- aggregation in the event selectors (src/dsmc/agg_event.cpp) ----
  public :: gran_dsmc_agg_options_default, gran_dsmc_create_agg, gran_scene_dsmc_agg_options
  ! ---- end aggregation in the event selectors ----
  ! ---- end cell selector ----
  ! ---- analysis ----
  ! A TAMSD plan: the C handle and the trajectory length it was made for (so that the wrappers can
  ! check the shape of the positions they pass).
  type, public :: gran_tamsd_plan
    type(c_ptr) :: ptr = c_null_ptr
    integer(c_int64_t) :: nsamples = 0
  end type gran_tamsd_plan
  public :: gran_tamsd_plan_create, gran_tamsd_plan_destroy, gran_tamsd_plan_execute, gran_tamsd, &
            gran_tamsd_direct, gran_sonine_a2, gran_speed_histogram
  ! ---- scenes and runs ----
  ! Scenes and runs. Handles (gran_scene, gran_mixture, gran_dsmc) are type(c_ptr).
  ! gran_run_control%progress: c_funloc of `integer(c_int) function f(p, params) bind(C)` with
  ! `type(gran_run_progress), intent(in) :: p` and `type(c_ptr), value :: params`.
  public :: gran_scene_load, gran_scene_parse, gran_scene_set, gran_scene_destroy, gran_scene_text, gran_scene_output_path, &
            gran_scene_sizes, gran_scene_times, gran_scene_lags, gran_scene_mixture, &
            gran_scene_initial_temperatures, gran_scene_dsmc_options, gran_scene_dsmc, gran_scene_run, &
            gran_scene_resume
  ! replicas and threads of a run (src/io/run.cpp)
  public :: gran_scene_set_replicas, gran_scene_replicas, gran_set_threads, gran_get_threads

  ! ---- GSRD (granular stochastic rotation dynamics, src/srd/) ----
  public :: gran_srd_options_default, gran_srd_create, gran_srd_destroy, gran_srd_advance, gran_srd_observe
  public :: gran_srd_stress_reset, gran_srd_particles, gran_srd_structure_factor
  public :: gran_srd_checkpoint_write, gran_srd_checkpoint_read
  public :: gran_srd_velocity_profile ! GSRD velocity profile
  ! ---- end GSRD ----

  ! ---- GSRD cell fields (src/srd/fields.cpp) ----
  public :: gran_srd_fields
  ! ---- end GSRD cell fields ----
  ! ---- GSRD devices (CUDA backend; src/srd/device_cuda.cpp) ----
  public :: gran_srd_set_device, gran_srd_get_device
  ! ---- end GSRD devices ----

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
    msg = gran_c_string(c_gran_strerror(int(code, c_int)))
  end function gran_strerror

  !> Copy of a static NUL-terminated C string.
  function gran_c_string(p) result(str)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: str
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: str)
    do i = 1, n
      str(i:i) = chars(i)
    end do
  end function gran_c_string

  !> Build configuration of the linked library (compiler, flags, CUDA).
  function gran_get_build_config() result(config)
    character(len=:), allocatable :: config
    type(c_ptr) :: p
    if (c_gran_get_build_config(p) /= GRAN_SUCCESS) then
      config = ''
    else
      config = gran_c_string(p)
    end if
  end function gran_get_build_config

  !> Forget the last error message of this thread.
  subroutine gran_clear_error(ierr)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_clear_error(), ierr)
  end subroutine gran_clear_error

  !> Number of warnings the library recorded in this thread.
  subroutine gran_warning_count(count, ierr)
    integer(c_int64_t), intent(out) :: count
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_warning_count(count), ierr)
  end subroutine gran_warning_count

  !> Text of the last warning recorded in this thread ('' when none).
  function gran_last_warning() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(1024)
    buf = c_null_char
    if (c_gran_last_warning_copy(buf, int(size(buf), c_int64_t)) /= 0) buf(1) = c_null_char
    msg = gran_buffer_string(buf)
  end function gran_last_warning

  !> Whether the CUDA backend was compiled in (1) or not (0).
  subroutine gran_cuda_compiled(compiled, ierr)
    integer, intent(out) :: compiled
    integer, intent(out), optional :: ierr
    integer(c_int) :: c
    c = 0
    call gran_check(c_gran_cuda_compiled(c), ierr)
    compiled = int(c)
  end subroutine gran_cuda_compiled

  !> Number of visible CUDA devices (0 without a GPU or without the CUDA backend).
  subroutine gran_cuda_device_count(count, ierr)
    integer, intent(out) :: count
    integer, intent(out), optional :: ierr
    integer(c_int) :: c
    c = 0
    call gran_check(c_gran_cuda_device_count(c), ierr)
    count = int(c)
  end subroutine gran_cuda_device_count

  !> Message of the last failure in this thread.
  function gran_last_error_message() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(1024)
    buf = c_null_char
    if (c_gran_last_error_copy(buf, int(size(buf), c_int64_t)) /= 0) buf(1) = c_null_char
    msg = gran_buffer_string(buf)
  end function gran_last_error_message

  !> Where the last failure in this thread was detected (library function and source line).
  function gran_last_error_location() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(512)
    buf = c_null_char
    if (c_gran_last_error_location_copy(buf, int(size(buf), c_int64_t)) /= 0) buf(1) = c_null_char
    msg = gran_buffer_string(buf)
  end function gran_last_error_location

  !> The characters of buf up to its first NUL.
  function gran_buffer_string(buf) result(str)
    character(kind=c_char), intent(in) :: buf(:)
    character(len=:), allocatable :: str
    integer :: i, n
    n = 0
    do while (n < size(buf))
      if (buf(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: str)
    do i = 1, n
      str(i:i) = buf(i)
    end do
  end function gran_buffer_string

  !> Hand a C status to the optional ierr; without ierr, stop with the message on failure.
  subroutine gran_check(status, ierr)
    integer(c_int), intent(in) :: status
    integer, intent(out), optional :: ierr
    if (present(ierr)) then
      ierr = int(status)
    else if (status /= GRAN_SUCCESS) then
      write(error_unit, '(a)') 'granary: ' // gran_strerror(int(status)) // ': ' // gran_last_error_message()
      flush(error_unit) ! before the stop: an exit handler (a leak checker, MPI) may end the process unflushed
      error stop 1
    end if
  end subroutine gran_check

  !> Record a failure a wrapper found itself (wrong array sizes): gran_last_error_message() returns
  !> `message` afterwards; ierr = code, or (without ierr) stop with the message on stderr.
  subroutine gran_set_error_message(code, message, ierr)
    integer, intent(in) :: code
    character(len=*), intent(in) :: message
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable :: cmsg(:)
    integer :: i
    allocate(cmsg(len(message) + 1))
    do i = 1, len(message)
      cmsg(i) = message(i:i)
    end do
    cmsg(len(message) + 1) = c_null_char
    call gran_check(c_gran_set_error_message(int(code, c_int), cmsg), ierr)
  end subroutine gran_set_error_message

  !> "NAME has N elements, expected M" (the sizes of a wrapper's array check)
  function gran_size_text(name, n, need) result(s)
    character(len=*), intent(in) :: name
    integer(c_int64_t), intent(in) :: n, need
    character(len=:), allocatable :: s
    character(len=24) :: a, b
    write(a, '(i0)') n
    write(b, '(i0)') need
    s = name // ' has ' // trim(a) // ' elements, expected ' // trim(b)
  end function gran_size_text

  ! ---- foundation (rng, segtree, particles, abi) ----
  !> A wrapper found arrays of inconsistent shapes before calling C: ierr = GRAN_ERR_ARG, or (without
  !> ierr) stop with the message, as gran_check does.
  subroutine gran_core_shape_error(what, ierr)
    character(len=*), intent(in) :: what
    integer, intent(out), optional :: ierr
    call gran_set_error_message(int(GRAN_ERR_ARG), what, ierr)
  end subroutine gran_core_shape_error

  ! ---- rng ---------------------------------------------------------------------------------------
  !> State = four splitmix64 outputs of seed (the bits of a uint64_t).
  subroutine gran_rng_seed(rng, seed, ierr)
    type(gran_rng), intent(out) :: rng
    integer(c_int64_t), intent(in) :: seed
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_seed(rng, seed), ierr)
  end subroutine gran_rng_seed

  !> Stream stream_id of seed: the seeded state advanced by stream_id * 2^128 steps.
  subroutine gran_rng_stream(seed, stream_id, rng, ierr)
    integer(c_int64_t), intent(in) :: seed, stream_id
    type(gran_rng), intent(out) :: rng
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_stream(seed, stream_id, rng), ierr)
  end subroutine gran_rng_stream

  !> Advance by 2^128 steps.
  subroutine gran_rng_jump(rng, ierr)
    type(gran_rng), intent(inout) :: rng
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_jump(rng), ierr)
  end subroutine gran_rng_jump

  !> Advance by 2^192 steps.
  subroutine gran_rng_long_jump(rng, ierr)
    type(gran_rng), intent(inout) :: rng
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_long_jump(rng), ierr)
  end subroutine gran_rng_long_jump

  !> size(x) raw 64-bit outputs (bits of uint64_t).
  subroutine gran_rng_u64(rng, x, ierr)
    type(gran_rng), intent(inout) :: rng
    integer(c_int64_t), intent(out) :: x(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_u64(rng, size(x, kind=c_int64_t), x), ierr)
  end subroutine gran_rng_u64

  !> size(x) uniforms in [0,1).
  subroutine gran_rng_uniform(rng, x, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: x(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_uniform(rng, size(x, kind=c_int64_t), x), ierr)
  end subroutine gran_rng_uniform

  !> size(x) uniforms in (0,1].
  subroutine gran_rng_uniform_pos(rng, x, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: x(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_uniform_pos(rng, size(x, kind=c_int64_t), x), ierr)
  end subroutine gran_rng_uniform_pos

  !> size(x) exponential deviates of mean 1.
  subroutine gran_rng_exponential(rng, x, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: x(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_exponential(rng, size(x, kind=c_int64_t), x), ierr)
  end subroutine gran_rng_exponential

  !> size(x) standard normal deviates.
  subroutine gran_rng_normal(rng, x, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: x(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_rng_normal(rng, size(x, kind=c_int64_t), x), ierr)
  end subroutine gran_rng_normal

  !> Unit vectors e(3, n), uniform on the sphere.
  subroutine gran_rng_unit_vector3(rng, e, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: e(:,:)
    integer, intent(out), optional :: ierr
    if (size(e, 1) /= 3) then
      call gran_core_shape_error('gran_rng_unit_vector3: e must have shape (3, n)', ierr)
      return
    end if
    call gran_check(c_gran_rng_unit_vector3(rng, size(e, 2, kind=c_int64_t), e), ierr)
  end subroutine gran_rng_unit_vector3

  !> Unit vectors e(2, n), uniform on the circle.
  subroutine gran_rng_unit_vector2(rng, e, ierr)
    type(gran_rng), intent(inout) :: rng
    real(c_double), intent(out) :: e(:,:)
    integer, intent(out), optional :: ierr
    if (size(e, 1) /= 2) then
      call gran_core_shape_error('gran_rng_unit_vector2: e must have shape (2, n)', ierr)
      return
    end if
    call gran_check(c_gran_rng_unit_vector2(rng, size(e, 2, kind=c_int64_t), e), ierr)
  end subroutine gran_rng_unit_vector2

  !> GPU: x(:, k) = size(x, 1) uniforms from states(k) (not advanced); GRAN_ERR_UNSUPPORTED
  !> without the CUDA backend or a GPU.
  subroutine gran_cuda_rng_uniform(states, x, ierr)
    type(gran_rng), intent(in) :: states(:)
    real(c_double), intent(out) :: x(:,:)
    integer, intent(out), optional :: ierr
    if (size(x, 2) /= size(states)) then
      call gran_core_shape_error('gran_cuda_rng_uniform: x must have shape (n, size(states))', ierr)
      return
    end if
    call gran_check(c_gran_cuda_rng_uniform(states, size(states, kind=c_int64_t), &
                                            size(x, 1, kind=c_int64_t), x), ierr)
  end subroutine gran_cuda_rng_uniform

  ! ---- segment tree ------------------------------------------------------------------------------
  !> Sum tree over the size(w) >= 1 weights w (>= 0). Free an initialised tree first.
  subroutine gran_segtree_init(t, w, ierr)
    type(gran_segtree), intent(inout) :: t
    real(c_double), intent(in) :: w(:)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_init(t, size(w, kind=c_int64_t), w), ierr)
  end subroutine gran_segtree_init

  !> Release the nodes (safe on a freed tree).
  subroutine gran_segtree_free(t, ierr)
    type(gran_segtree), intent(inout) :: t
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_free(t), ierr)
  end subroutine gran_segtree_free

  !> Weight of leaf i (1-based) := w.
  subroutine gran_segtree_set(t, i, w, ierr)
    type(gran_segtree), intent(inout) :: t
    integer, intent(in) :: i
    real(c_double), intent(in) :: w
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_set(t, int(i, c_int64_t) - 1, w), ierr)
  end subroutine gran_segtree_set

  !> Weights of leaves idx(k) (1-based) := w(k), parents recomputed once.
  subroutine gran_segtree_set_batch(t, idx, w, ierr)
    type(gran_segtree), intent(inout) :: t
    integer, intent(in) :: idx(:)
    real(c_double), intent(in) :: w(:)
    integer, intent(out), optional :: ierr
    if (size(w) /= size(idx)) then
      call gran_core_shape_error('gran_segtree_set_batch: idx and w differ in size', ierr)
      return
    end if
    call gran_check(c_gran_segtree_set_batch(t, size(idx, kind=c_int64_t), int(idx, c_int64_t) - 1, w), ierr)
  end subroutine gran_segtree_set_batch

  !> w = weight of leaf i (1-based).
  subroutine gran_segtree_get(t, i, w, ierr)
    type(gran_segtree), intent(in) :: t
    integer, intent(in) :: i
    real(c_double), intent(out) :: w
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_get(t, int(i, c_int64_t) - 1, w), ierr)
  end subroutine gran_segtree_get

  !> Sum of the weights.
  subroutine gran_segtree_total(t, total, ierr)
    type(gran_segtree), intent(in) :: t
    real(c_double), intent(out) :: total
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_total(t, total), ierr)
  end subroutine gran_segtree_total

  !> Leaf index (1-based) with probability w(i)/total from one uniform u in [0,1).
  subroutine gran_segtree_sample(t, u, index, ierr)
    type(gran_segtree), intent(in) :: t
    real(c_double), intent(in) :: u
    integer, intent(out) :: index
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: i0
    integer(c_int) :: status
    i0 = -1
    status = c_gran_segtree_sample(t, u, i0)
    index = int(i0 + 1)
    call gran_check(status, ierr)
  end subroutine gran_segtree_sample

  !> Recompute the internal nodes from the leaves.
  subroutine gran_segtree_rebuild(t, ierr)
    type(gran_segtree), intent(inout) :: t
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_segtree_rebuild(t), ierr)
  end subroutine gran_segtree_rebuild

  ! ---- particles ---------------------------------------------------------------------------------
  !> Empty particle set with room for capacity particles; flags: OR (ior) of GRAN_PARTICLES_*.
  subroutine gran_particles_init(p, capacity, flags, ierr)
    type(gran_particles), intent(inout) :: p
    integer, intent(in) :: capacity, flags
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_particles_init(p, int(capacity, c_int64_t), int(flags, c_int)), ierr)
  end subroutine gran_particles_init

  !> Release every array and zero p.
  subroutine gran_particles_free(p, ierr)
    type(gran_particles), intent(inout) :: p
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_particles_free(p), ierr)
  end subroutine gran_particles_free

  !> Room for at least capacity particles (never shrinks).
  subroutine gran_particles_reserve(p, capacity, ierr)
    type(gran_particles), intent(inout) :: p
    integer, intent(in) :: capacity
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_particles_reserve(p, int(capacity, c_int64_t)), ierr)
  end subroutine gran_particles_reserve

  !> Append a particle with velocity v(3) and (0-based) species; index = its slot (1-based).
  subroutine gran_particles_add(p, v, species, index, ierr)
    type(gran_particles), intent(inout) :: p
    real(c_double), intent(in) :: v(3)
    integer, intent(in) :: species
    integer, intent(out), optional :: index
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: i0
    i0 = -1
    call gran_check(c_gran_particles_add(p, v, int(species, c_int32_t), i0), ierr)
    if (present(index)) index = int(i0 + 1)
  end subroutine gran_particles_add

  !> Remove particle i (1-based): the last particle moves into slot i.
  subroutine gran_particles_swap_remove(p, i, ierr)
    type(gran_particles), intent(inout) :: p
    integer, intent(in) :: i
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_particles_swap_remove(p, int(i, c_int64_t) - 1), ierr)
  end subroutine gran_particles_swap_remove

  !> Bytes held by the arrays.
  subroutine gran_particles_memory(p, bytes, ierr)
    type(gran_particles), intent(in) :: p
    integer(c_int64_t), intent(out) :: bytes
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_particles_memory(p, bytes), ierr)
  end subroutine gran_particles_memory

  !> View v(3, n) of the velocities (disassociated when nothing is allocated).
  function gran_particles_view_v(p) result(v)
    type(gran_particles), intent(in) :: p
    real(c_double), pointer :: v(:,:)
    nullify(v)
    if (c_associated(p%v)) call c_f_pointer(p%v, v, [3_c_int64_t, p%n])
  end function gran_particles_view_v

  !> View species(n) (0-based species indices).
  function gran_particles_view_species(p) result(s)
    type(gran_particles), intent(in) :: p
    integer(c_int32_t), pointer :: s(:)
    nullify(s)
    if (c_associated(p%species)) call c_f_pointer(p%species, s, [p%n])
  end function gran_particles_view_species

  !> View r(3, n) of the displacements (disassociated without GRAN_PARTICLES_DISPLACEMENT).
  function gran_particles_view_r(p) result(r)
    type(gran_particles), intent(in) :: p
    real(c_double), pointer :: r(:,:)
    nullify(r)
    if (c_associated(p%r)) call c_f_pointer(p%r, r, [3_c_int64_t, p%n])
  end function gran_particles_view_r

  !> View t_last(n) (disassociated without GRAN_PARTICLES_DISPLACEMENT).
  function gran_particles_view_t_last(p) result(t)
    type(gran_particles), intent(in) :: p
    real(c_double), pointer :: t(:)
    nullify(t)
    if (c_associated(p%t_last)) call c_f_pointer(p%t_last, t, [p%n])
  end function gran_particles_view_t_last

  !> View x(3, n) of the positions (disassociated without GRAN_PARTICLES_POSITION).
  function gran_particles_view_x(p) result(x)
    type(gran_particles), intent(in) :: p
    real(c_double), pointer :: x(:,:)
    nullify(x)
    if (c_associated(p%x)) call c_f_pointer(p%x, x, [3_c_int64_t, p%n])
  end function gran_particles_view_x

  !> View mass(n) (disassociated without GRAN_PARTICLES_MASS).
  function gran_particles_view_mass(p) result(m)
    type(gran_particles), intent(in) :: p
    real(c_double), pointer :: m(:)
    nullify(m)
    if (c_associated(p%mass)) call c_f_pointer(p%mass, m, [p%n])
  end function gran_particles_view_mass

  ! ---- ABI ---------------------------------------------------------------------------------------
  !> value = sizeof of a struct ('sizeof(gran_rng)') or value of an enum constant ('GRAN_ERR_ARG').
  subroutine gran_abi_query(name, value, ierr)
    character(len=*), intent(in) :: name
    integer(c_int64_t), intent(out) :: value
    integer, intent(out), optional :: ierr
    value = -huge(value)
    call gran_check(c_gran_abi_query(trim(name) // c_null_char, value), ierr)
  end subroutine gran_abi_query
  ! ---- kinetic theory ----
  ! ---- theory: helpers ---------------------------------------------------------------------------
  !> Number of species of mix (0 when the handle is not valid: the C call then reports that).
  function gran_theory_m(mix) result(m)
    type(c_ptr), intent(in) :: mix
    integer(c_int64_t) :: m
    if (c_gran_mixture_nspecies(mix, m) /= GRAN_SUCCESS) m = 0
  end function gran_theory_m

  !> An array of the wrong size: ierr = GRAN_ERR_ARG, or (without ierr) stop with the message.
  subroutine gran_theory_shape_error(what, ierr)
    character(len=*), intent(in) :: what
    integer, intent(out), optional :: ierr
    call gran_set_error_message(int(GRAN_ERR_ARG), what, ierr)
  end subroutine gran_theory_shape_error

  !> .true. (and the error handled) when size(a) < need for a valid mixture.
  logical function gran_theory_short(a_size, need, what, ierr)
    integer, intent(in) :: a_size
    integer(c_int64_t), intent(in) :: need
    character(len=*), intent(in) :: what
    integer, intent(out), optional :: ierr
    gran_theory_short = need > 0 .and. int(a_size, c_int64_t) < need
    if (gran_theory_short) call gran_theory_shape_error(what // ' (' // gran_size_text('it', int(a_size, c_int64_t), need) &
                                                        // ')', ierr)
  end function gran_theory_short

  ! ---- theory: mixture ---------------------------------------------------------------------------
  !> Mixture of size(density) species; mass, sigma optional (defaults m_k = k, sigma_k = k^(1/3)).
  subroutine gran_mixture_create(mix, density, mass, sigma, ierr)
    type(c_ptr), intent(out) :: mix
    real(c_double), intent(in) :: density(:)
    real(c_double), intent(in), target, contiguous, optional :: mass(:), sigma(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pm, ps
    mix = c_null_ptr
    pm = c_null_ptr
    ps = c_null_ptr
    if (present(mass)) then
      if (size(mass) /= size(density)) then
        call gran_theory_shape_error('gran_mixture_create: size(mass) /= size(density)', ierr)
        return
      end if
      if (size(mass) > 0) pm = c_loc(mass(1))
    end if
    if (present(sigma)) then
      if (size(sigma) /= size(density)) then
        call gran_theory_shape_error('gran_mixture_create: size(sigma) /= size(density)', ierr)
        return
      end if
      if (size(sigma) > 0) ps = c_loc(sigma(1))
    end if
    call gran_check(c_gran_mixture_create(size(density, kind=c_int64_t), pm, ps, density, mix), ierr)
  end subroutine gran_mixture_create

  !> n_k = n1 k^-theta, m_k = k m1, sigma_k = sigma1 k^(1/3).
  subroutine gran_mixture_create_powerlaw(mix, nspecies, m1, sigma1, n1, theta, ierr)
    type(c_ptr), intent(out) :: mix
    integer(c_int64_t), intent(in) :: nspecies
    real(c_double), intent(in) :: m1, sigma1, n1, theta
    integer, intent(out), optional :: ierr
    mix = c_null_ptr
    call gran_check(c_gran_mixture_create_powerlaw(nspecies, m1, sigma1, n1, theta, mix), ierr)
  end subroutine gran_mixture_create_powerlaw

  !> Release the mixture; mix becomes c_null_ptr (NULL-safe).
  subroutine gran_mixture_destroy(mix, ierr)
    type(c_ptr), intent(inout) :: mix
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_destroy(mix), ierr)
  end subroutine gran_mixture_destroy

  subroutine gran_mixture_nspecies(mix, nspecies, ierr)
    type(c_ptr), intent(in) :: mix
    integer(c_int64_t), intent(out) :: nspecies
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_nspecies(mix, nspecies), ierr)
  end subroutine gran_mixture_nspecies

  !> Masses, diameters, densities (each optional, size >= M).
  subroutine gran_mixture_get(mix, mass, sigma, density, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(out), target, contiguous, optional :: mass(:), sigma(:), density(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pm, ps, pn
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    pm = c_null_ptr
    ps = c_null_ptr
    pn = c_null_ptr
    if (present(mass)) then
      if (gran_theory_short(size(mass), m, 'gran_mixture_get: size(mass) < M', ierr)) return
      if (size(mass) > 0) pm = c_loc(mass(1))
    end if
    if (present(sigma)) then
      if (gran_theory_short(size(sigma), m, 'gran_mixture_get: size(sigma) < M', ierr)) return
      if (size(sigma) > 0) ps = c_loc(sigma(1))
    end if
    if (present(density)) then
      if (gran_theory_short(size(density), m, 'gran_mixture_get: size(density) < M', ierr)) return
      if (size(density) > 0) pn = c_loc(density(1))
    end if
    call gran_check(c_gran_mixture_get(mix, pm, ps, pn), ierr)
  end subroutine gran_mixture_get

  subroutine gran_mixture_set_restitution(mix, eps, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: eps
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_set_restitution(mix, eps), ierr)
  end subroutine gran_mixture_set_restitution

  !> Symmetric eps(M, M).
  subroutine gran_mixture_set_restitution_matrix(mix, eps, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: eps(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (m > 0 .and. (size(eps, 1, kind=c_int64_t) /= m .or. size(eps, 2, kind=c_int64_t) /= m)) then
      call gran_theory_shape_error('gran_mixture_set_restitution_matrix: eps must be M x M', ierr)
      return
    end if
    call gran_check(c_gran_mixture_set_restitution_matrix(mix, eps), ierr)
  end subroutine gran_mixture_set_restitution_matrix

  subroutine gran_mixture_set_viscoelastic(mix, beta, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: beta
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_set_viscoelastic(mix, beta), ierr)
  end subroutine gran_mixture_set_viscoelastic

  !> Symmetric beta(M, M).
  subroutine gran_mixture_set_viscoelastic_matrix(mix, beta, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: beta(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (m > 0 .and. (size(beta, 1, kind=c_int64_t) /= m .or. size(beta, 2, kind=c_int64_t) /= m)) then
      call gran_theory_shape_error('gran_mixture_set_viscoelastic_matrix: beta must be M x M', ierr)
      return
    end if
    call gran_check(c_gran_mixture_set_viscoelastic_matrix(mix, beta), ierr)
  end subroutine gran_mixture_set_viscoelastic_matrix

  !> beta_ij = (3/2) A (rho/m_eff)^(2/5), rho = 2 Y sqrt(R_eff)/(3 (1 - nu^2)), R = sigma/2.
  subroutine gran_mixture_set_viscoelastic_material(mix, a, y, nu, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: a, y, nu
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_set_viscoelastic_material(mix, a, y, nu), ierr)
  end subroutine gran_mixture_set_viscoelastic_material

  subroutine gran_mixture_set_g2(mix, g2, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: g2
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_mixture_set_g2(mix, g2), ierr)
  end subroutine gran_mixture_set_g2

  subroutine gran_mixture_set_g2_matrix(mix, g2, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: g2(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (m > 0 .and. (size(g2, 1, kind=c_int64_t) /= m .or. size(g2, 2, kind=c_int64_t) /= m)) then
      call gran_theory_shape_error('gran_mixture_set_g2_matrix: g2 must be M x M', ierr)
      return
    end if
    call gran_check(c_gran_mixture_set_g2_matrix(mix, g2), ierr)
  end subroutine gran_mixture_set_g2_matrix

  !> GRAN_RESTITUTION_CONSTANT, _MATRIX or _VISCOELASTIC.
  subroutine gran_mixture_restitution_model(mix, model, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(out) :: model
    integer, intent(out), optional :: ierr
    integer(c_int) :: cm
    cm = -1
    call gran_check(c_gran_mixture_restitution_model(mix, cm), ierr)
    model = int(cm)
  end subroutine gran_mixture_restitution_model

  !> Pair (i, k), 1-based: eps (NaN for viscoelastic), beta, g2 (each optional).
  subroutine gran_mixture_pair(mix, i, k, eps, beta, g2, ierr)
    type(c_ptr), intent(in) :: mix
    integer(c_int64_t), intent(in) :: i, k
    real(c_double), intent(out), target, optional :: eps, beta, g2
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pe, pb, pg
    pe = c_null_ptr
    pb = c_null_ptr
    pg = c_null_ptr
    if (present(eps)) pe = c_loc(eps)
    if (present(beta)) pb = c_loc(beta)
    if (present(g2)) pg = c_loc(g2)
    call gran_check(c_gran_mixture_pair(mix, i - 1, k - 1, pe, pb, pg), ierr)
  end subroutine gran_mixture_pair

  ! ---- theory: viscoelastic restitution -----------------------------------------------------------
  subroutine gran_viscoelastic_eps(x, eps, ierr)
    real(c_double), intent(in) :: x
    real(c_double), intent(out) :: eps
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_viscoelastic_eps(x, eps), ierr)
  end subroutine gran_viscoelastic_eps

  subroutine gran_viscoelastic_eps_vn(beta, vn, eps, ierr)
    real(c_double), intent(in) :: beta, vn
    real(c_double), intent(out) :: eps
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_viscoelastic_eps_vn(beta, vn, eps), ierr)
  end subroutine gran_viscoelastic_eps_vn

  ! ---- theory: rates, times, HCS ---------------------------------------------------------------------
  !> Cooling rates xi(M) at temperatures temp(M) (Eq. 14-15 / A7).
  subroutine gran_theory_cooling_rates(mix, temp, xi, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: xi(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_cooling_rates: size(temp) < M', ierr)) return
    if (gran_theory_short(size(xi), m, 'gran_theory_cooling_rates: size(xi) < M', ierr)) return
    call gran_check(c_gran_theory_cooling_rates(mix, temp, xi), ierr)
  end subroutine gran_theory_cooling_rates

  subroutine gran_theory_tau_v(mix, temp, tau_v, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: tau_v(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_tau_v: size(temp) < M', ierr)) return
    if (gran_theory_short(size(tau_v), m, 'gran_theory_tau_v: size(tau_v) < M', ierr)) return
    call gran_check(c_gran_theory_tau_v(mix, temp, tau_v), ierr)
  end subroutine gran_theory_tau_v

  subroutine gran_theory_diffusion(mix, temp, d, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: d(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_diffusion: size(temp) < M', ierr)) return
    if (gran_theory_short(size(d), m, 'gran_theory_diffusion: size(d) < M', ierr)) return
    call gran_check(c_gran_theory_diffusion(mix, temp, d), ierr)
  end subroutine gran_theory_diffusion

  subroutine gran_theory_collision_rate1(mix, temp, inv_tau_c, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: inv_tau_c
    integer, intent(out), optional :: ierr
    if (gran_theory_short(size(temp), gran_theory_m(mix), 'gran_theory_collision_rate1: size(temp) < M', ierr)) return
    call gran_check(c_gran_theory_collision_rate1(mix, temp, inv_tau_c), ierr)
  end subroutine gran_theory_collision_rate1

  !> HCS temperatures t0(M) with norm GRAN_HCS_NORM_MEAN or GRAN_HCS_NORM_T1; tau0 (huge -> inf).
  subroutine gran_theory_hcs(mix, norm, val, t0, tau0, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: norm
    real(c_double), intent(in) :: val
    real(c_double), intent(out) :: t0(:)
    real(c_double), intent(out), optional :: tau0
    integer, intent(out), optional :: ierr
    real(c_double) :: tau
    if (gran_theory_short(size(t0), gran_theory_m(mix), 'gran_theory_hcs: size(t0) < M', ierr)) return
    tau = 0
    call gran_check(c_gran_theory_hcs(mix, int(norm, c_int), val, t0, tau), ierr)
    if (present(tau0)) tau0 = tau
  end subroutine gran_theory_hcs

  !> HCS in the approximation GRAN_THEORY_MAXWELLIAN or GRAN_THEORY_SONINE: t0(M), a2(M) (zeros at
  !> the Maxwellian level), tau0 (huge -> inf).
  subroutine gran_theory_hcs_approx(mix, approx, norm, val, t0, a2, tau0, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx, norm
    real(c_double), intent(in) :: val
    real(c_double), intent(out) :: t0(:), a2(:)
    real(c_double), intent(out), optional :: tau0
    integer, intent(out), optional :: ierr
    real(c_double) :: tau
    if (gran_theory_short(size(t0), gran_theory_m(mix), 'gran_theory_hcs_approx: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a2), gran_theory_m(mix), 'gran_theory_hcs_approx: size(a2) < M', ierr)) return
    tau = 0
    call gran_check(c_gran_theory_hcs_approx(mix, int(approx, c_int), int(norm, c_int), val, t0, a2, tau), ierr)
    if (present(tau0)) tau0 = tau
  end subroutine gran_theory_hcs_approx

  !> Diffusion coefficients d(M) at temp(M), a2(M), zeta(M) (cooling rates) in either approximation
  !> (Sonine: the two-moment velocity correlation).
  subroutine gran_theory_diffusion_approx(mix, approx, temp, a2, zeta, d, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx
    real(c_double), intent(in) :: temp(:), a2(:), zeta(:)
    real(c_double), intent(out) :: d(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_diffusion_approx: size(temp) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_diffusion_approx: size(a2) < M', ierr)) return
    if (gran_theory_short(size(zeta), m, 'gran_theory_diffusion_approx: size(zeta) < M', ierr)) return
    if (gran_theory_short(size(d), m, 'gran_theory_diffusion_approx: size(d) < M', ierr)) return
    call gran_check(c_gran_theory_diffusion_approx(mix, int(approx, c_int), temp, a2, zeta, d), ierr)
  end subroutine gran_theory_diffusion_approx

  !> MSD in the HCS (t0(M), a2(M), tau0 of gran_theory_hcs_approx) in either approximation:
  !> msd(M, size(t)), msd_total(size(t)) optional.
  subroutine gran_theory_msd_hcs_approx(mix, approx, t0, a2, tau0, t, msd, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx
    real(c_double), intent(in) :: t0(:), a2(:), tau0, t(:)
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: pt
    m = gran_theory_m(mix)
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd_hcs_approx: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_msd_hcs_approx: size(a2) < M', ierr)) return
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd_hcs_approx: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd_hcs_approx: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd_hcs_approx(mix, int(approx, c_int), t0, a2, tau0, size(t, kind=c_int64_t), t, &
                                                 msd, pt), ierr)
  end subroutine gran_theory_msd_hcs_approx

  !> First Sonine rates at (temp(M), a2(M)): zeta(M) and da2dt(M).
  subroutine gran_theory_sonine_rates(mix, temp, a2, zeta, da2dt, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:), a2(:)
    real(c_double), intent(out) :: zeta(:), da2dt(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_sonine_rates: size(temp) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_sonine_rates: size(a2) < M', ierr)) return
    if (gran_theory_short(size(zeta), m, 'gran_theory_sonine_rates: size(zeta) < M', ierr)) return
    if (gran_theory_short(size(da2dt), m, 'gran_theory_sonine_rates: size(da2dt) < M', ierr)) return
    call gran_check(c_gran_theory_sonine_rates(mix, temp, a2, zeta, da2dt), ierr)
  end subroutine gran_theory_sonine_rates

  !> HCS of the second Sonine approximation: t0(M), a2(M), a3(M), tau0 (huge -> inf).
  subroutine gran_theory_hcs_sonine2(mix, norm, val, t0, a2, a3, tau0, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: norm
    real(c_double), intent(in) :: val
    real(c_double), intent(out) :: t0(:), a2(:), a3(:)
    real(c_double), intent(out), optional :: tau0
    integer, intent(out), optional :: ierr
    real(c_double) :: tau
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_hcs_sonine2: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_hcs_sonine2: size(a2) < M', ierr)) return
    if (gran_theory_short(size(a3), m, 'gran_theory_hcs_sonine2: size(a3) < M', ierr)) return
    tau = 0
    call gran_check(c_gran_theory_hcs_sonine2(mix, int(norm, c_int), val, t0, a2, a3, tau), ierr)
    if (present(tau0)) tau0 = tau
  end subroutine gran_theory_hcs_sonine2

  !> Second Sonine rates at temp(M), a2(M), a3(M): zeta(M), da2dt(M), da3dt(M).
  subroutine gran_theory_sonine2_rates(mix, temp, a2, a3, zeta, da2dt, da3dt, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:), a2(:), a3(:)
    real(c_double), intent(out) :: zeta(:), da2dt(:), da3dt(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_sonine2_rates: size(temp) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_sonine2_rates: size(a2) < M', ierr)) return
    if (gran_theory_short(size(a3), m, 'gran_theory_sonine2_rates: size(a3) < M', ierr)) return
    if (gran_theory_short(size(zeta), m, 'gran_theory_sonine2_rates: size(zeta) < M', ierr)) return
    if (gran_theory_short(size(da2dt), m, 'gran_theory_sonine2_rates: size(da2dt) < M', ierr)) return
    if (gran_theory_short(size(da3dt), m, 'gran_theory_sonine2_rates: size(da3dt) < M', ierr)) return
    call gran_check(c_gran_theory_sonine2_rates(mix, temp, a2, a3, zeta, da2dt, da3dt), ierr)
  end subroutine gran_theory_sonine2_rates

  !> Second Sonine trajectory: temp(M, size(t)) from t0(M), a20(M), a30(M) (absent: 0); a2, a3 (M, size(t)) optional.
  subroutine gran_theory_temperatures_sonine2(mix, t0, t, rtol, temp, a20, a30, a2, a3, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: temp(:, :)
    real(c_double), intent(in), target, contiguous, optional :: a20(:), a30(:)
    real(c_double), intent(out), target, contiguous, optional :: a2(:, :), a3(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: p20, p30, p2, p3
    m = gran_theory_m(mix)
    p20 = c_null_ptr
    p30 = c_null_ptr
    p2 = c_null_ptr
    p3 = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_temperatures_sonine2: size(t0) < M', ierr)) return
    if (present(a20)) then
      if (gran_theory_short(size(a20), m, 'gran_theory_temperatures_sonine2: size(a20) < M', ierr)) return
      if (size(a20) > 0) p20 = c_loc(a20(1))
    end if
    if (present(a30)) then
      if (gran_theory_short(size(a30), m, 'gran_theory_temperatures_sonine2: size(a30) < M', ierr)) return
      if (size(a30) > 0) p30 = c_loc(a30(1))
    end if
    if (m > 0 .and. (size(temp, 1, kind=c_int64_t) /= m .or. size(temp, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_temperatures_sonine2: temp must be (M, size(t))', ierr)
      return
    end if
    if (present(a2)) then
      if (m > 0 .and. (size(a2, 1, kind=c_int64_t) /= m .or. size(a2, 2) /= size(t))) then
        call gran_theory_shape_error('gran_theory_temperatures_sonine2: a2 must be (M, size(t))', ierr)
        return
      end if
      if (size(a2) > 0) p2 = c_loc(a2(1, 1))
    end if
    if (present(a3)) then
      if (m > 0 .and. (size(a3, 1, kind=c_int64_t) /= m .or. size(a3, 2) /= size(t))) then
        call gran_theory_shape_error('gran_theory_temperatures_sonine2: a3 must be (M, size(t))', ierr)
        return
      end if
      if (size(a3) > 0) p3 = c_loc(a3(1, 1))
    end if
    call gran_check(c_gran_theory_temperatures_sonine2(mix, t0, p20, p30, size(t, kind=c_int64_t), t, rtol, temp, &
                    p2, p3), ierr)
  end subroutine gran_theory_temperatures_sonine2

  !> HCS of the linear Sonine hierarchy to order nmax (2..5): t0(M), a(M*(nmax-1)) with a((k-1)*(nmax-1) + q-1) =
  !> a_q of species k, tau0 (huge -> inf).
  subroutine gran_theory_hcs_sonine_n(mix, nmax, norm, val, t0, a, tau0, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: nmax, norm
    real(c_double), intent(in) :: val
    real(c_double), intent(out) :: t0(:), a(:)
    real(c_double), intent(out), optional :: tau0
    integer, intent(out), optional :: ierr
    real(c_double) :: tau
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_hcs_sonine_n: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a), m * max(nmax - 1, 1), 'gran_theory_hcs_sonine_n: size(a) < M*(nmax-1)', ierr)) return
    tau = 0
    call gran_check(c_gran_theory_hcs_sonine_n(mix, int(nmax, c_int), int(norm, c_int), val, t0, a, tau), ierr)
    if (present(tau0)) tau0 = tau
  end subroutine gran_theory_hcs_sonine_n

  !> temp(M, size(t)) and a2(M, size(t)) from t0(M), a20(M) in either approximation.
  subroutine gran_theory_temperatures_approx(mix, approx, t0, a20, t, rtol, temp, a2, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx
    real(c_double), intent(in) :: t0(:), a20(:), t(:), rtol
    real(c_double), intent(out) :: temp(:, :), a2(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_temperatures_approx: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a20), m, 'gran_theory_temperatures_approx: size(a20) < M', ierr)) return
    if (m > 0 .and. (size(temp, 1, kind=c_int64_t) /= m .or. size(temp, 2) /= size(t) .or. &
        size(a2, 1, kind=c_int64_t) /= m .or. size(a2, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_temperatures_approx: temp and a2 must be (M, size(t))', ierr)
      return
    end if
    call gran_check(c_gran_theory_temperatures_approx(mix, int(approx, c_int), t0, a20, size(t, kind=c_int64_t), t, &
                    rtol, temp, a2), ierr)
  end subroutine gran_theory_temperatures_approx

  !> temp(M, size(t)) from t0(M) by Eq. 13.
  subroutine gran_theory_temperatures(mix, t0, t, rtol, temp, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: temp(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_temperatures: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(temp, 1, kind=c_int64_t) /= m .or. size(temp, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_temperatures: temp must be (M, size(t))', ierr)
      return
    end if
    call gran_check(c_gran_theory_temperatures(mix, t0, size(t, kind=c_int64_t), t, rtol, temp), ierr)
  end subroutine gran_theory_temperatures

  !> temp(M, size(t)) of a driven mixture from t0(M): Eq. 13 with heating(M) (optional, dT_k/dt of
  !> the white-noise thermostat) and a Maxwellian bath (bath_density > 0; 0: none).
  subroutine gran_theory_temperatures_driven(mix, t0, bath_density, bath_mass, bath_t, bath_sigma, t, rtol, temp, &
                                             heating, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), bath_density, bath_mass, bath_t, bath_sigma, t(:), rtol
    real(c_double), intent(out) :: temp(:, :)
    real(c_double), intent(in), target, contiguous, optional :: heating(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: ph
    m = gran_theory_m(mix)
    ph = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_temperatures_driven: size(t0) < M', ierr)) return
    if (present(heating)) then
      if (gran_theory_short(size(heating), m, 'gran_theory_temperatures_driven: size(heating) < M', ierr)) return
      if (size(heating) > 0) ph = c_loc(heating(1))
    end if
    if (m > 0 .and. (size(temp, 1, kind=c_int64_t) /= m .or. size(temp, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_temperatures_driven: temp must be (M, size(t))', ierr)
      return
    end if
    call gran_check(c_gran_theory_temperatures_driven(mix, t0, ph, bath_density, bath_mass, bath_t, bath_sigma, &
                    size(t, kind=c_int64_t), t, rtol, temp), ierr)
  end subroutine gran_theory_temperatures_driven

  ! ---- theory: MSD, TAMSD --------------------------------------------------------------------------
  !> Eq. 22: msd(M, size(t)), optional msd_total(size(t)) (Eq. 3).
  subroutine gran_theory_msd_hcs(mix, t0, tau0, t, msd, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), tau0, t(:)
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: pt
    m = gran_theory_m(mix)
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd_hcs: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd_hcs: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd_hcs: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd_hcs(mix, t0, tau0, size(t, kind=c_int64_t), t, msd, pt), ierr)
  end subroutine gran_theory_msd_hcs

  !> Eq. 4 by numerical integration from any start t0(M).
  subroutine gran_theory_msd(mix, t0, t, rtol, msd, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: pt
    m = gran_theory_m(mix)
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd(mix, t0, size(t, kind=c_int64_t), t, rtol, msd, pt), ierr)
  end subroutine gran_theory_msd

  !> Eq. 4 from any start t0(M) in either approximation (Sonine: the two-moment correlation).
  subroutine gran_theory_msd_approx(mix, approx, t0, t, rtol, msd, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: pt
    m = gran_theory_m(mix)
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd_approx: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd_approx: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd_approx: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd_approx(mix, int(approx, c_int), t0, size(t, kind=c_int64_t), t, rtol, msd, pt), ierr)
  end subroutine gran_theory_msd_approx

  !> Eq. 4 on the first Sonine trajectory from t0(M) and a20(M) (absent: 0); correlation_a2
  !> (absent: .false.) puts the a2(t1) of all species into the two-moment correlation.
  subroutine gran_theory_msd_sonine(mix, t0, t, rtol, msd, a20, correlation_a2, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(in), target, contiguous, optional :: a20(:)
    logical, intent(in), optional :: correlation_a2
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    integer(c_int) :: ca
    type(c_ptr) :: pa, pt
    m = gran_theory_m(mix)
    ca = 0
    if (present(correlation_a2)) then
      if (correlation_a2) ca = 1
    end if
    pa = c_null_ptr
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd_sonine: size(t0) < M', ierr)) return
    if (present(a20)) then
      if (gran_theory_short(size(a20), m, 'gran_theory_msd_sonine: size(a20) < M', ierr)) return
      if (size(a20) > 0) pa = c_loc(a20(1))
    end if
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd_sonine: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd_sonine: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd_sonine(mix, t0, pa, ca, size(t, kind=c_int64_t), t, rtol, msd, pt), ierr)
  end subroutine gran_theory_msd_sonine

  !> Eq. 4 on the second Sonine trajectory from t0(M), a20(M) and a30(M) (absent: 0); correlation_a2
  !> (absent: .false.) puts the a2(t1) of all species into the two-moment correlation.
  subroutine gran_theory_msd_sonine2(mix, t0, t, rtol, msd, a20, a30, correlation_a2, msd_total, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: msd(:, :)
    real(c_double), intent(in), target, contiguous, optional :: a20(:), a30(:)
    logical, intent(in), optional :: correlation_a2
    real(c_double), intent(out), target, contiguous, optional :: msd_total(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    integer(c_int) :: ca
    type(c_ptr) :: pa, pb, pt
    m = gran_theory_m(mix)
    ca = 0
    if (present(correlation_a2)) then
      if (correlation_a2) ca = 1
    end if
    pa = c_null_ptr
    pb = c_null_ptr
    pt = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_msd_sonine2: size(t0) < M', ierr)) return
    if (present(a20)) then
      if (gran_theory_short(size(a20), m, 'gran_theory_msd_sonine2: size(a20) < M', ierr)) return
      if (size(a20) > 0) pa = c_loc(a20(1))
    end if
    if (present(a30)) then
      if (gran_theory_short(size(a30), m, 'gran_theory_msd_sonine2: size(a30) < M', ierr)) return
      if (size(a30) > 0) pb = c_loc(a30(1))
    end if
    if (m > 0 .and. (size(msd, 1, kind=c_int64_t) /= m .or. size(msd, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_msd_sonine2: msd must be (M, size(t))', ierr)
      return
    end if
    if (present(msd_total)) then
      if (size(msd_total) /= size(t)) then
        call gran_theory_shape_error('gran_theory_msd_sonine2: size(msd_total) /= size(t)', ierr)
        return
      end if
      if (size(msd_total) > 0) pt = c_loc(msd_total(1))
    end if
    call gran_check(c_gran_theory_msd_sonine2(mix, t0, pa, pb, ca, size(t, kind=c_int64_t), t, rtol, msd, pt), ierr)
  end subroutine gran_theory_msd_sonine2

  !> Eq. 27: tamsd(M, size(lag)) over the measurement time t_meas.
  subroutine gran_theory_tamsd(mix, t0, tau0, t_meas, lag, rtol, tamsd, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), tau0, t_meas, lag(:), rtol
    real(c_double), intent(out) :: tamsd(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_tamsd: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(tamsd, 1, kind=c_int64_t) /= m .or. size(tamsd, 2) /= size(lag))) then
      call gran_theory_shape_error('gran_theory_tamsd: tamsd must be (M, size(lag))', ierr)
      return
    end if
    call gran_check(c_gran_theory_tamsd(mix, t0, tau0, t_meas, size(lag, kind=c_int64_t), lag, rtol, tamsd), ierr)
  end subroutine gran_theory_tamsd

  !> The TAMSD in the HCS (t0(M), a2(M), tau0 of gran_theory_hcs_approx) in either approximation:
  !> tamsd(M, size(lag)).
  subroutine gran_theory_tamsd_approx(mix, approx, t0, a2, tau0, t_meas, lag, rtol, tamsd, ierr)
    type(c_ptr), intent(in) :: mix
    integer, intent(in) :: approx
    real(c_double), intent(in) :: t0(:), a2(:), tau0, t_meas, lag(:), rtol
    real(c_double), intent(out) :: tamsd(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_tamsd_approx: size(t0) < M', ierr)) return
    if (gran_theory_short(size(a2), m, 'gran_theory_tamsd_approx: size(a2) < M', ierr)) return
    if (m > 0 .and. (size(tamsd, 1, kind=c_int64_t) /= m .or. size(tamsd, 2) /= size(lag))) then
      call gran_theory_shape_error('gran_theory_tamsd_approx: tamsd must be (M, size(lag))', ierr)
      return
    end if
    call gran_check(c_gran_theory_tamsd_approx(mix, int(approx, c_int), t0, a2, tau0, t_meas, &
                                               size(lag, kind=c_int64_t), lag, rtol, tamsd), ierr)
  end subroutine gran_theory_tamsd_approx

  !> The TAMSD on the sample grid j*dt, j = 0..nsamples-1 (lags in samples): tamsd(M, size(lag)).
  subroutine gran_theory_tamsd_sampled(mix, t0, tau0, dt, nsamples, lag, rtol, tamsd, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), tau0, dt, rtol
    integer(c_int64_t), intent(in) :: nsamples, lag(:)
    real(c_double), intent(out) :: tamsd(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_tamsd_sampled: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(tamsd, 1, kind=c_int64_t) /= m .or. size(tamsd, 2) /= size(lag))) then
      call gran_theory_shape_error('gran_theory_tamsd_sampled: tamsd must be (M, size(lag))', ierr)
      return
    end if
    call gran_check(c_gran_theory_tamsd_sampled(mix, t0, tau0, dt, nsamples, size(lag, kind=c_int64_t), lag, rtol, &
                    tamsd), ierr)
  end subroutine gran_theory_tamsd_sampled

  !> The two terms of Eq. 27: delta0(M, size(lag)) and xi(M, size(lag)), each optional.
  subroutine gran_theory_tamsd_parts(mix, t0, tau0, t_meas, lag, rtol, delta0, xi, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), tau0, t_meas, lag(:), rtol
    real(c_double), intent(out), target, contiguous, optional :: delta0(:, :), xi(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    type(c_ptr) :: pd, px
    m = gran_theory_m(mix)
    pd = c_null_ptr
    px = c_null_ptr
    if (gran_theory_short(size(t0), m, 'gran_theory_tamsd_parts: size(t0) < M', ierr)) return
    if (present(delta0)) then
      if (m > 0 .and. (size(delta0, 1, kind=c_int64_t) /= m .or. size(delta0, 2) /= size(lag))) then
        call gran_theory_shape_error('gran_theory_tamsd_parts: delta0 must be (M, size(lag))', ierr)
        return
      end if
      if (size(delta0) > 0) pd = c_loc(delta0(1, 1))
    end if
    if (present(xi)) then
      if (m > 0 .and. (size(xi, 1, kind=c_int64_t) /= m .or. size(xi, 2) /= size(lag))) then
        call gran_theory_shape_error('gran_theory_tamsd_parts: xi must be (M, size(lag))', ierr)
        return
      end if
      if (size(xi) > 0) px = c_loc(xi(1, 1))
    end if
    call gran_check(c_gran_theory_tamsd_parts(mix, t0, tau0, t_meas, size(lag, kind=c_int64_t), lag, rtol, pd, px), &
                    ierr)
  end subroutine gran_theory_tamsd_parts

  !> Eq. 31 for species 1 of a monodisperse gas (others tracers): msd(size(t)), tau0 (Eq. 29) optional.
  subroutine gran_theory_msd_mono(mix, t1, t, msd, tau0, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t1, t(:)
    real(c_double), intent(out) :: msd(:)
    real(c_double), intent(out), optional :: tau0
    integer, intent(out), optional :: ierr
    real(c_double) :: tau
    if (size(msd) /= size(t)) then
      call gran_theory_shape_error('gran_theory_msd_mono: size(msd) /= size(t)', ierr)
      return
    end if
    tau = 0
    call gran_check(c_gran_theory_msd_mono(mix, t1, size(t, kind=c_int64_t), t, msd, tau), ierr)
    if (present(tau0)) tau0 = tau
  end subroutine gran_theory_msd_mono

  !> Reduced times tau(M, size(t)) of Eq. 6 (units of tau_c(0)).
  subroutine gran_theory_reduced_time(mix, t0, t, rtol, tau, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), t(:), rtol
    real(c_double), intent(out) :: tau(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_reduced_time: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(tau, 1, kind=c_int64_t) /= m .or. size(tau, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_reduced_time: tau must be (M, size(t))', ierr)
      return
    end if
    call gran_check(c_gran_theory_reduced_time(mix, t0, size(t, kind=c_int64_t), t, rtol, tau), ierr)
  end subroutine gran_theory_reduced_time

  ! ---- theory: tracer limit -------------------------------------------------------------------------
  !> Eqs. 34-35: gamma = T_tracer/T_1 for species `tracer` (1-based, >= 2).
  subroutine gran_theory_tracer_gamma_approx(mix, tracer, gamma, ierr)
    type(c_ptr), intent(in) :: mix
    integer(c_int64_t), intent(in) :: tracer
    real(c_double), intent(out) :: gamma
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_theory_tracer_gamma_approx(mix, tracer - 1, gamma), ierr)
  end subroutine gran_theory_tracer_gamma_approx

  !> Eq. 33: tau_v,tracer/tau_c(0) for a given gamma (tracer 1-based, >= 2).
  subroutine gran_theory_tracer_tau_v_hat(mix, tracer, gamma, tau_v_hat, ierr)
    type(c_ptr), intent(in) :: mix
    integer(c_int64_t), intent(in) :: tracer
    real(c_double), intent(in) :: gamma
    real(c_double), intent(out) :: tau_v_hat
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_theory_tracer_tau_v_hat(mix, tracer - 1, gamma, tau_v_hat), ierr)
  end subroutine gran_theory_tracer_tau_v_hat

  ! ---- theory: collisions (the DSMC outline) ------------------------------------------------------
  !> <|g_ij|> (Eq. 60) as g(M, M).
  subroutine gran_theory_mean_relative_speed(mix, temp, g, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: g(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_mean_relative_speed: size(temp) < M', ierr)) return
    if (m > 0 .and. (size(g, 1, kind=c_int64_t) /= m .or. size(g, 2, kind=c_int64_t) /= m)) then
      call gran_theory_shape_error('gran_theory_mean_relative_speed: g must be M x M', ierr)
      return
    end if
    call gran_check(c_gran_theory_mean_relative_speed(mix, temp, g), ierr)
  end subroutine gran_theory_mean_relative_speed

  !> Collisions per unit volume and time per species pair, rates(M, M) (each unordered pair once).
  subroutine gran_theory_collision_rates(mix, temp, rates, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: temp(:)
    real(c_double), intent(out) :: rates(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(temp), m, 'gran_theory_collision_rates: size(temp) < M', ierr)) return
    if (m > 0 .and. (size(rates, 1, kind=c_int64_t) /= m .or. size(rates, 2, kind=c_int64_t) /= m)) then
      call gran_theory_shape_error('gran_theory_collision_rates: rates must be M x M', ierr)
      return
    end if
    call gran_check(c_gran_theory_collision_rates(mix, temp, rates), ierr)
  end subroutine gran_theory_collision_rates

  !> Expected collisions in volume along the cooling from t0: counts(M, M, size(t)).
  subroutine gran_theory_collision_counts(mix, t0, volume, t, rtol, counts, ierr)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), volume, t(:), rtol
    real(c_double), intent(out) :: counts(:, :, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_collision_counts: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(counts, 1, kind=c_int64_t) /= m .or. size(counts, 2, kind=c_int64_t) /= m .or. &
                     size(counts, 3) /= size(t))) then
      call gran_theory_shape_error('gran_theory_collision_counts: counts must be (M, M, size(t))', ierr)
      return
    end if
    call gran_check(c_gran_theory_collision_counts(mix, t0, volume, size(t, kind=c_int64_t), t, rtol, counts), ierr)
  end subroutine gran_theory_collision_counts

  ! ---- theory: aggregation and fragmentation kinetics ---------------------------------------------
  !> Maxwellian fractions of the collisions of a pair (i, j) that stick and that shatter.
  subroutine gran_theory_agg_fractions(mi, mj, ti, tj, e_agg, e_frag, f_stick, f_frag, ierr)
    real(c_double), intent(in) :: mi, mj, ti, tj, e_agg, e_frag
    real(c_double), intent(out) :: f_stick, f_frag
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_theory_agg_fractions(mi, mj, ti, tj, e_agg, e_frag, f_stick, f_frag), ierr)
  end subroutine gran_theory_agg_fractions

  !> Smoluchowski kinetics with temperatures: n(M, size(t)), optional temp(M, size(t)) and
  !> overflow(3, size(t)) (number, mass, energy per volume beyond size M). e_frag = huge: none.
  !> frag_law (optional, GRAN_FRAG_*; default monomers): gran_theory_aggregation_law.
  subroutine gran_theory_aggregation(mix, t0, e_agg, e_frag, eps_f, t, rtol, n, temp, overflow, ierr, frag_law)
    type(c_ptr), intent(in) :: mix
    real(c_double), intent(in) :: t0(:), e_agg, e_frag, eps_f, t(:), rtol
    real(c_double), intent(out) :: n(:, :)
    real(c_double), intent(out), target, contiguous, optional :: temp(:, :), overflow(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int32_t), intent(in), optional :: frag_law
    integer(c_int64_t) :: m
    type(c_ptr) :: pt, po
    m = gran_theory_m(mix)
    if (gran_theory_short(size(t0), m, 'gran_theory_aggregation: size(t0) < M', ierr)) return
    if (m > 0 .and. (size(n, 1, kind=c_int64_t) /= m .or. size(n, 2) /= size(t))) then
      call gran_theory_shape_error('gran_theory_aggregation: n must be (M, size(t))', ierr)
      return
    end if
    pt = c_null_ptr
    po = c_null_ptr
    if (present(temp)) then
      if (size(temp, 1, kind=c_int64_t) /= m .or. size(temp, 2) /= size(t)) then
        call gran_theory_shape_error('gran_theory_aggregation: temp must be (M, size(t))', ierr)
        return
      end if
      pt = c_loc(temp)
    end if
    if (present(overflow)) then
      if (size(overflow, 1) /= 3 .or. size(overflow, 2) /= size(t)) then
        call gran_theory_shape_error('gran_theory_aggregation: overflow must be (3, size(t))', ierr)
        return
      end if
      po = c_loc(overflow)
    end if
    if (present(frag_law)) then ! aggregation in the event selectors block
      call gran_check(c_gran_theory_aggregation_law(mix, t0, e_agg, e_frag, eps_f, int(frag_law, c_int), &
                                                    size(t, kind=c_int64_t), t, rtol, n, pt, po), ierr)
      return
    end if
    call gran_check(c_gran_theory_aggregation(mix, t0, e_agg, e_frag, eps_f, size(t, kind=c_int64_t), t, rtol, &
                                              n, pt, po), ierr)
  end subroutine gran_theory_aggregation

  !> Constant-kernel Smoluchowski equations: n(size(n0), size(t)), optional overflow(3, size(t)).
  subroutine gran_theory_smoluchowski_constant(k, n0, t, rtol, n, overflow, ierr)
    real(c_double), intent(in) :: k, n0(:), t(:), rtol
    real(c_double), intent(out) :: n(:, :)
    real(c_double), intent(out), target, contiguous, optional :: overflow(:, :)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: po
    if (size(n, 1) /= size(n0) .or. size(n, 2) /= size(t)) then
      call gran_theory_shape_error('gran_theory_smoluchowski_constant: n must be (size(n0), size(t))', ierr)
      return
    end if
    po = c_null_ptr
    if (present(overflow)) then
      if (size(overflow, 1) /= 3 .or. size(overflow, 2) /= size(t)) then
        call gran_theory_shape_error('gran_theory_smoluchowski_constant: overflow must be (3, size(t))', ierr)
        return
      end if
      po = c_loc(overflow)
    end if
    call gran_check(c_gran_theory_smoluchowski_constant(size(n0, kind=c_int64_t), k, n0, size(t, kind=c_int64_t), &
                                                        t, rtol, n, po), ierr)
  end subroutine gran_theory_smoluchowski_constant
  ! ---- DSMC engines ----
  !> Array of the wrong size handed to a DSMC wrapper: ierr = GRAN_ERR_ARG, or stop with the message.
  subroutine gran_dsmc_shape_error(what, ierr)
    character(len=*), intent(in) :: what
    integer, intent(out), optional :: ierr
    call gran_set_error_message(int(GRAN_ERR_ARG), what, ierr)
  end subroutine gran_dsmc_shape_error

  !> Number of species of an engine (0 when sim is not valid; the C call then reports it).
  function gran_dsmc_m(sim) result(m)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t) :: m
    type(gran_dsmc_stats) :: st
    m = 0
    if (c_gran_dsmc_get_stats(sim, st) == GRAN_SUCCESS) m = st%nspecies
  end function gran_dsmc_m

  !> Defaults: low-rank selector, no observables, seed 1, volume 0, bound_refresh 0 (= N).
  subroutine gran_dsmc_options_default(opt, ierr)
    type(gran_dsmc_options), intent(out) :: opt
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_options_default(opt), ierr)
  end subroutine gran_dsmc_options_default

  !> New engine for mixture mix: counts(M) particles per species (absent: round(n_k V) with
  !> opt%volume), Maxwellian at T0(M) (absent: the HCS with <T(0)> = 1), zero momentum.
  subroutine gran_dsmc_create(sim, mix, opt, counts, T0, ierr)
    type(c_ptr), intent(out) :: sim
    type(c_ptr), intent(in) :: mix
    type(gran_dsmc_options), intent(in) :: opt
    integer(c_int64_t), intent(in), target, contiguous, optional :: counts(:)
    real(c_double), intent(in), target, contiguous, optional :: T0(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pc, pt
    integer(c_int64_t) :: m
    sim = c_null_ptr
    pc = c_null_ptr
    pt = c_null_ptr
    m = -1
    if (c_gran_mixture_nspecies(mix, m) /= GRAN_SUCCESS) m = -1
    if (present(counts)) then
      if (m >= 0 .and. size(counts, kind=c_int64_t) /= m) then
        call gran_dsmc_shape_error('gran_dsmc_create: size(counts) /= number of species', ierr)
        return
      end if
      if (size(counts) > 0) pc = c_loc(counts(1))
    end if
    if (present(T0)) then
      if (m >= 0 .and. size(T0, kind=c_int64_t) /= m) then
        call gran_dsmc_shape_error('gran_dsmc_create: size(T0) /= number of species', ierr)
        return
      end if
      if (size(T0) > 0) pt = c_loc(T0(1))
    end if
    call gran_check(c_gran_dsmc_create(mix, pc, pt, opt, sim), ierr)
  end subroutine gran_dsmc_create

  !> Release the engine; sim becomes c_null_ptr (NULL-safe).
  subroutine gran_dsmc_destroy(sim, ierr)
    type(c_ptr), intent(inout) :: sim
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_destroy(sim), ierr)
  end subroutine gran_dsmc_destroy

  !> Simulate up to time t_end.
  subroutine gran_dsmc_advance(sim, t_end, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(in) :: t_end
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_advance(sim, t_end), ierr)
  end subroutine gran_dsmc_advance

  !> Simulate the next n accepted collisions.
  subroutine gran_dsmc_advance_collisions(sim, n, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(in) :: n
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_advance_collisions(sim, n), ierr)
  end subroutine gran_dsmc_advance_collisions

  subroutine gran_dsmc_time(sim, t, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out) :: t
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_time(sim, t), ierr)
  end subroutine gran_dsmc_time

  subroutine gran_dsmc_get_stats(sim, stats, ierr)
    type(c_ptr), intent(in) :: sim
    type(gran_dsmc_stats), intent(out) :: stats
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_get_stats(sim, stats), ierr)
  end subroutine gran_dsmc_get_stats

  !> Particles per species (M).
  subroutine gran_dsmc_counts(sim, counts, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(out), contiguous :: counts(:)
    integer, intent(out), optional :: ierr
    if (size(counts, kind=c_int64_t) /= gran_dsmc_m(sim)) then
      call gran_dsmc_shape_error('gran_dsmc_counts: size(counts) /= number of species', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_counts(sim, counts), ierr)
  end subroutine gran_dsmc_counts

  !> Partial temperatures (M), NaN for an empty species.
  subroutine gran_dsmc_temperatures(sim, T, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out), contiguous :: T(:)
    integer, intent(out), optional :: ierr
    if (size(T, kind=c_int64_t) /= gran_dsmc_m(sim)) then
      call gran_dsmc_shape_error('gran_dsmc_temperatures: size(T) /= number of species', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_temperatures(sim, T), ierr)
  end subroutine gran_dsmc_temperatures

  !> Partial MSDs (M) and the number-weighted total (optional); needs GRAN_OBSERVE_DISPLACEMENT.
  subroutine gran_dsmc_msd(sim, msd, msd_total, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out), target, contiguous :: msd(:)
    real(c_double), intent(out), target, optional :: msd_total
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pt
    if (size(msd, kind=c_int64_t) /= gran_dsmc_m(sim) .or. size(msd) == 0) then
      call gran_dsmc_shape_error('gran_dsmc_msd: size(msd) /= number of species', ierr)
      return
    end if
    pt = c_null_ptr
    if (present(msd_total)) pt = c_loc(msd_total)
    call gran_check(c_gran_dsmc_msd(sim, c_loc(msd(1)), pt), ierr)
  end subroutine gran_dsmc_msd

  !> Collisions per species pair, counts(M, M) (symmetric); needs GRAN_OBSERVE_COLLISION_COUNTS.
  subroutine gran_dsmc_collision_counts(sim, counts, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(out), contiguous :: counts(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m
    m = gran_dsmc_m(sim)
    if (size(counts, 1, kind=c_int64_t) /= m .or. size(counts, 2, kind=c_int64_t) /= m) then
      call gran_dsmc_shape_error('gran_dsmc_collision_counts: counts is not (M, M)', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_collision_counts(sim, counts), ierr)
  end subroutine gran_dsmc_collision_counts

  !> Sonine coefficient a2 per species (M).
  subroutine gran_dsmc_sonine_a2(sim, a2, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out), contiguous :: a2(:)
    integer, intent(out), optional :: ierr
    if (size(a2, kind=c_int64_t) /= gran_dsmc_m(sim)) then
      call gran_dsmc_shape_error('gran_dsmc_sonine_a2: size(a2) /= number of species', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_sonine_a2(sim, a2), ierr)
  end subroutine gran_dsmc_sonine_a2

  !> Energy ledger: kinetic energy now, at the start, dissipated (any may be absent).
  subroutine gran_dsmc_energy(sim, e_kin, e_initial, e_dissipated, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out), target, optional :: e_kin, e_initial, e_dissipated
    integer, intent(out), optional :: ierr
    type(c_ptr) :: a, b, c
    a = c_null_ptr
    b = c_null_ptr
    c = c_null_ptr
    if (present(e_kin)) a = c_loc(e_kin)
    if (present(e_initial)) b = c_loc(e_initial)
    if (present(e_dissipated)) c = c_loc(e_dissipated)
    call gran_check(c_gran_dsmc_energy(sim, a, b, c), ierr)
  end subroutine gran_dsmc_energy

  subroutine gran_dsmc_momentum(sim, p, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), intent(out) :: p(3)
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_momentum(sim, p), ierr)
  end subroutine gran_dsmc_momentum

  !> Borrowed view of the particle arrays (valid while the engine lives, read only).
  subroutine gran_dsmc_particles(sim, p, ierr)
    type(c_ptr), intent(in) :: sim
    type(gran_particles), pointer, intent(out) :: p
    integer, intent(out), optional :: ierr
    type(c_ptr) :: cp
    integer(c_int) :: status
    nullify(p)
    cp = c_null_ptr
    status = c_gran_dsmc_particles(sim, cp)
    if (status == GRAN_SUCCESS) call c_f_pointer(cp, p)
    call gran_check(status, ierr)
  end subroutine gran_dsmc_particles

  !> Species offsets (M+1, 0-based particle indices): species k occupies offsets(k)..offsets(k+1)-1.
  subroutine gran_dsmc_species_offsets(sim, offsets, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(out), contiguous :: offsets(:)
    integer, intent(out), optional :: ierr
    if (size(offsets, kind=c_int64_t) /= gran_dsmc_m(sim) + 1) then
      call gran_dsmc_shape_error('gran_dsmc_species_offsets: size(offsets) /= M + 1', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_species_offsets(sim, offsets), ierr)
  end subroutine gran_dsmc_species_offsets

  !> Copy of the velocities of species k (1-based) into v(3, counts(k)), in the order of the particle
  !> view without trajectories; no memory beyond v (the view with speed classes is a kept copy).
  subroutine gran_dsmc_species_velocities(sim, k, v, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(in) :: k
    real(c_double), intent(out), contiguous :: v(:, :)
    integer, intent(out), optional :: ierr
    integer(c_int64_t), allocatable :: cnt(:)
    integer :: st
    allocate(cnt(gran_dsmc_m(sim)))
    if (k < 1 .or. k > size(cnt, kind=c_int64_t)) then
      call gran_check(c_gran_dsmc_species_velocities(sim, k - 1, v), ierr) ! the library names the bad k
      return
    end if
    call gran_dsmc_counts(sim, cnt, st)
    if (st /= 0) then
      call gran_check(int(st, c_int), ierr)
      return
    end if
    if (size(v, 1) /= 3 .or. size(v, 2, kind=c_int64_t) /= cnt(k)) then
      call gran_dsmc_shape_error('gran_dsmc_species_velocities: shape(v) /= [3, counts(k)]', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_species_velocities(sim, k - 1, v), ierr)
  end subroutine gran_dsmc_species_velocities

  !> Borrowed trajectories xyz(3, nsamples, ntraj) (NaN where not reached yet) and the species of
  !> each tracer (0-based, optional); needs GRAN_OBSERVE_TRAJECTORIES.
  subroutine gran_dsmc_trajectories(sim, xyz, species, ierr)
    type(c_ptr), intent(in) :: sim
    real(c_double), pointer, intent(out) :: xyz(:, :, :)
    integer(c_int32_t), pointer, intent(out), optional :: species(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: nt, ns
    type(c_ptr) :: px, ps
    integer(c_int) :: status
    nullify(xyz)
    if (present(species)) nullify(species)
    nt = 0
    ns = 0
    status = c_gran_dsmc_trajectories(sim, nt, ns, px, ps)
    if (status == GRAN_SUCCESS .and. nt > 0 .and. ns > 0) then
      call c_f_pointer(px, xyz, [3_c_int64_t, ns, nt])
      if (present(species)) call c_f_pointer(ps, species, [nt])
    end if
    call gran_check(status, ierr)
  end subroutine gran_dsmc_trajectories

  !> Complete engine state into group `group` of HDF5 file `path` (created if missing).
  subroutine gran_dsmc_checkpoint_write(sim, path, group, ierr)
    type(c_ptr), intent(in) :: sim
    character(len=*), intent(in) :: path, group
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_checkpoint_write(sim, trim(path) // c_null_char, trim(group) // c_null_char), ierr)
  end subroutine gran_dsmc_checkpoint_write

  !> New engine from a checkpoint; mix must be the mixture it was made with.
  subroutine gran_dsmc_checkpoint_read(sim, path, group, mix, ierr)
    type(c_ptr), intent(out) :: sim
    character(len=*), intent(in) :: path, group
    type(c_ptr), intent(in) :: mix
    integer, intent(out), optional :: ierr
    sim = c_null_ptr
    call gran_check(c_gran_dsmc_checkpoint_read(trim(path) // c_null_char, trim(group) // c_null_char, mix, sim), &
                    ierr)
  end subroutine gran_dsmc_checkpoint_read
  ! ---- analysis ----
  !> Plan for trajectories of nsamples samples; release with gran_tamsd_plan_destroy.
  subroutine gran_tamsd_plan_create(nsamples, plan, ierr)
    integer, intent(in) :: nsamples
    type(gran_tamsd_plan), intent(out) :: plan
    integer, intent(out), optional :: ierr
    integer(c_int) :: status
    status = c_gran_tamsd_plan_create(int(nsamples, c_int64_t), plan%ptr)
    if (status == GRAN_SUCCESS) plan%nsamples = nsamples
    call gran_check(status, ierr)
  end subroutine gran_tamsd_plan_create

  !> Release a plan (safe on a released one).
  subroutine gran_tamsd_plan_destroy(plan, ierr)
    type(gran_tamsd_plan), intent(inout) :: plan
    integer, intent(out), optional :: ierr
    plan%nsamples = 0
    call gran_check(c_gran_tamsd_plan_destroy(plan%ptr), ierr)
  end subroutine gran_tamsd_plan_destroy

  !> tamsd(1 + L) = TAMSD at lag L samples, L = 0 .. size(tamsd)-1, averaged over the
  !> trajectories xyz(3, nsamples, ntraj).
  subroutine gran_tamsd_plan_execute(plan, xyz, tamsd, ierr)
    type(gran_tamsd_plan), intent(in) :: plan
    real(c_double), intent(in) :: xyz(:,:,:)
    real(c_double), intent(out) :: tamsd(:)
    integer, intent(out), optional :: ierr
    if (size(xyz, 1) /= 3 .or. size(xyz, 2, kind=c_int64_t) /= plan%nsamples) then
      call gran_core_shape_error('gran_tamsd_plan_execute: xyz must have shape (3, nsamples of the plan, ntraj)', ierr)
      return
    end if
    call gran_check(c_gran_tamsd_plan_execute(plan%ptr, size(xyz, 3, kind=c_int64_t), xyz, &
                                              size(tamsd, kind=c_int64_t), tamsd), ierr)
  end subroutine gran_tamsd_plan_execute

  !> One-shot TAMSD by FFT of the trajectories xyz(3, nsamples, ntraj) for lags 0 .. size(tamsd)-1.
  subroutine gran_tamsd(xyz, tamsd, ierr)
    real(c_double), intent(in) :: xyz(:,:,:)
    real(c_double), intent(out) :: tamsd(:)
    integer, intent(out), optional :: ierr
    if (size(xyz, 1) /= 3) then
      call gran_core_shape_error('gran_tamsd: xyz must have shape (3, nsamples, ntraj)', ierr)
      return
    end if
    call gran_check(c_gran_tamsd(size(xyz, 3, kind=c_int64_t), size(xyz, 2, kind=c_int64_t), xyz, &
                                 size(tamsd, kind=c_int64_t), tamsd), ierr)
  end subroutine gran_tamsd

  !> The same by the direct sum (reference).
  subroutine gran_tamsd_direct(xyz, tamsd, ierr)
    real(c_double), intent(in) :: xyz(:,:,:)
    real(c_double), intent(out) :: tamsd(:)
    integer, intent(out), optional :: ierr
    if (size(xyz, 1) /= 3) then
      call gran_core_shape_error('gran_tamsd_direct: xyz must have shape (3, nsamples, ntraj)', ierr)
      return
    end if
    call gran_check(c_gran_tamsd_direct(size(xyz, 3, kind=c_int64_t), size(xyz, 2, kind=c_int64_t), xyz, &
                                        size(tamsd, kind=c_int64_t), tamsd), ierr)
  end subroutine gran_tamsd_direct

  !> Sonine a2 of the velocities v(3, n) relative to the mean flow; mass(n) optional.
  subroutine gran_sonine_a2(v, a2, mass, ierr)
    real(c_double), intent(in) :: v(:,:)
    real(c_double), intent(out) :: a2
    real(c_double), intent(in), target, contiguous, optional :: mass(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pm
    if (size(v, 1) /= 3) then
      call gran_core_shape_error('gran_sonine_a2: v must have shape (3, n)', ierr)
      return
    end if
    pm = c_null_ptr
    if (present(mass)) then
      if (size(mass) /= size(v, 2)) then
        call gran_core_shape_error('gran_sonine_a2: mass must have size(v, 2) elements', ierr)
        return
      end if
      pm = c_loc(mass)
    end if
    call gran_check(c_gran_sonine_a2(size(v, 2, kind=c_int64_t), v, pm, a2), ierr)
  end subroutine gran_sonine_a2

  !> hist(k) = density of c = |v - u|/scale in bin k of [0, cmax) (size(hist) bins);
  !> nbeyond = particles with c >= cmax.
  subroutine gran_speed_histogram(v, scale, cmax, hist, nbeyond, ierr)
    real(c_double), intent(in) :: v(:,:)
    real(c_double), intent(in) :: scale, cmax
    real(c_double), intent(out) :: hist(:)
    integer, intent(out), optional :: nbeyond
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: nb
    if (size(v, 1) /= 3) then
      call gran_core_shape_error('gran_speed_histogram: v must have shape (3, n)', ierr)
      return
    end if
    nb = 0
    call gran_check(c_gran_speed_histogram(size(v, 2, kind=c_int64_t), v, scale, size(hist, kind=c_int64_t), &
                                           cmax, hist, nb), ierr)
    if (present(nbeyond)) nbeyond = int(nb)
  end subroutine gran_speed_histogram
  ! ---- scenes and runs ----
  !> Fortran string -> NUL-terminated C characters (private helper).
  subroutine io_to_c(s, c)
    character(len=*), intent(in) :: s
    character(kind=c_char), allocatable, intent(out) :: c(:)
    integer :: i
    allocate(c(len(s) + 1))
    do i = 1, len(s)
      c(i) = s(i:i)
    end do
    c(len(s) + 1) = c_null_char
  end subroutine io_to_c

  !> Borrowed C string -> Fortran string (private helper).
  subroutine io_from_c(p, s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable, intent(out) :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    n = 0
    if (c_associated(p)) n = int(c_strlen(p))
    allocate(character(len=n) :: s)
    if (n == 0) return
    call c_f_pointer(p, chars, [n])
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end subroutine io_from_c

  !> Load and validate a scene file; release with gran_scene_destroy.
  subroutine gran_scene_load(path, scene, ierr)
    character(len=*), intent(in) :: path
    type(c_ptr), intent(out) :: scene
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable :: cpath(:)
    call io_to_c(path, cpath)
    call gran_check(c_gran_scene_load(cpath, scene), ierr)
  end subroutine gran_scene_load

  !> Parse and validate a scene from text; `name` is used in messages.
  subroutine gran_scene_parse(text, name, scene, ierr)
    character(len=*), intent(in) :: text, name
    type(c_ptr), intent(out) :: scene
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable :: ctext(:), cname(:)
    call io_to_c(text, ctext)
    call io_to_c(name, cname)
    call gran_check(c_gran_scene_parse(ctext, cname, scene), ierr)
  end subroutine gran_scene_parse

  !> Override one scene key as if the file said `key = value` (key "table.key", value TOML text:
  !> '7', '"x.h5"', '[1.0, 2.0]'); the scene is validated again and is unchanged on failure.
  subroutine gran_scene_set(scene, key, value, ierr)
    type(c_ptr), intent(in) :: scene
    character(len=*), intent(in) :: key, value
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable :: ckey(:), cvalue(:)
    call io_to_c(key, ckey)
    call io_to_c(value, cvalue)
    call gran_check(c_gran_scene_set(scene, ckey, cvalue), ierr)
  end subroutine gran_scene_set

  !> Release a scene (safe on a released one).
  subroutine gran_scene_destroy(scene, ierr)
    type(c_ptr), intent(inout) :: scene
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_destroy(scene), ierr)
  end subroutine gran_scene_destroy

  !> The whole scene text.
  subroutine gran_scene_text(scene, text, ierr)
    type(c_ptr), intent(in) :: scene
    character(len=:), allocatable, intent(out) :: text
    integer, intent(out), optional :: ierr
    type(c_ptr) :: p
    p = c_null_ptr
    call gran_check(c_gran_scene_text(scene, p), ierr)
    call io_from_c(p, text)
  end subroutine gran_scene_text

  !> The scene's output path.
  subroutine gran_scene_output_path(scene, path, ierr)
    type(c_ptr), intent(in) :: scene
    character(len=:), allocatable, intent(out) :: path
    integer, intent(out), optional :: ierr
    type(c_ptr) :: p
    p = c_null_ptr
    call gran_check(c_gran_scene_output_path(scene, p), ierr)
    call io_from_c(p, path)
  end subroutine gran_scene_output_path

  !> Species, output times, TAMSD lags; start and end time.
  subroutine gran_scene_sizes(scene, nspecies, ntimes, nlags, t_start, t_end, ierr)
    type(c_ptr), intent(in) :: scene
    integer, intent(out) :: nspecies, ntimes, nlags
    real(c_double), intent(out) :: t_start, t_end
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m, nt, nl
    m = 0; nt = 0; nl = 0; t_start = 0; t_end = 0
    call gran_check(c_gran_scene_sizes(scene, m, nt, nl, t_start, t_end), ierr)
    nspecies = int(m); ntimes = int(nt); nlags = int(nl)
  end subroutine gran_scene_sizes

  !> Output times (size ntimes).
  subroutine gran_scene_times(scene, times, ierr)
    type(c_ptr), intent(in) :: scene
    real(c_double), intent(out) :: times(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m, nt, nl
    real(c_double) :: a, b
    integer(c_int) :: status
    status = c_gran_scene_sizes(scene, m, nt, nl, a, b)
    if (status == GRAN_SUCCESS .and. size(times) < nt) then
      call gran_set_error_message(int(GRAN_ERR_ARG), &
                                  'gran_scene_times: ' // gran_size_text('times', size(times, kind=c_int64_t), nt), ierr)
      return
    end if
    if (status == GRAN_SUCCESS) status = c_gran_scene_times(scene, times)
    call gran_check(status, ierr)
  end subroutine gran_scene_times

  !> TAMSD lags (size nlags; GRAN_ERR_STATE when the scene records no TAMSD).
  subroutine gran_scene_lags(scene, lags, ierr)
    type(c_ptr), intent(in) :: scene
    real(c_double), intent(out) :: lags(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: m, nt, nl
    real(c_double) :: a, b
    integer(c_int) :: status
    status = c_gran_scene_sizes(scene, m, nt, nl, a, b)
    if (status == GRAN_SUCCESS .and. size(lags) < nl) then
      call gran_set_error_message(int(GRAN_ERR_ARG), &
                                  'gran_scene_lags: ' // gran_size_text('lags', size(lags, kind=c_int64_t), nl), ierr)
      return
    end if
    if (status == GRAN_SUCCESS) status = c_gran_scene_lags(scene, lags)
    call gran_check(status, ierr)
  end subroutine gran_scene_lags

  !> A new mixture from the scene (release it with the theory module's destroy).
  subroutine gran_scene_mixture(scene, mix, ierr)
    type(c_ptr), intent(in) :: scene
    type(c_ptr), intent(out) :: mix
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_mixture(scene, mix), ierr)
  end subroutine gran_scene_mixture

  !> Initial temperatures T0(nspecies) and tau0 = 2/xi_1(T0).
  subroutine gran_scene_initial_temperatures(scene, mix, T0, tau0, ierr)
    type(c_ptr), intent(in) :: scene, mix
    real(c_double), intent(out) :: T0(:), tau0
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_initial_temperatures(scene, mix, T0, tau0), ierr)
  end subroutine gran_scene_initial_temperatures

  !> Engine options and particle numbers of the scene. opt = c_loc of a bind(C) mirror of
  !> gran_dsmc_options (target); counts(nspecies); have_counts = 1 when listed in the scene.
  subroutine gran_scene_dsmc_options(scene, opt, counts, have_counts, ierr)
    type(c_ptr), intent(in) :: scene, opt
    integer(c_int64_t), intent(out) :: counts(:)
    integer, intent(out) :: have_counts
    integer, intent(out), optional :: ierr
    integer(c_int) :: h
    h = 0
    call gran_check(c_gran_scene_dsmc_options(scene, opt, counts, h), ierr)
    have_counts = int(h)
  end subroutine gran_scene_dsmc_options

  !> A new engine as `granary run` creates it.
  subroutine gran_scene_dsmc(scene, mix, sim, ierr)
    type(c_ptr), intent(in) :: scene, mix
    type(c_ptr), intent(out) :: sim
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_dsmc(scene, mix, sim), ierr)
  end subroutine gran_scene_dsmc

  !> Run a scene. output / checkpoint absent: the scene's ("" checkpoint: none).
  subroutine gran_scene_run(scene, output, checkpoint, ctl, result, ierr)
    type(c_ptr), intent(in) :: scene
    character(len=*), intent(in), optional :: output, checkpoint
    type(gran_run_control), intent(in), optional, target :: ctl
    type(gran_run_result), intent(out), optional, target :: result
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable, target :: cout(:), cck(:)
    type(c_ptr) :: pout, pck, pctl, pres
    pout = c_null_ptr; pck = c_null_ptr; pctl = c_null_ptr; pres = c_null_ptr
    if (present(output)) then
      call io_to_c(output, cout)
      pout = c_loc(cout)
    end if
    if (present(checkpoint)) then
      call io_to_c(checkpoint, cck)
      pck = c_loc(cck)
    end if
    if (present(ctl)) pctl = c_loc(ctl)
    if (present(result)) pres = c_loc(result)
    call gran_check(c_gran_scene_run(scene, pout, pck, pctl, pres), ierr)
  end subroutine gran_scene_run

  !> Continue a run from its checkpoint (output absent: the path stored in the checkpoint).
  subroutine gran_scene_resume(checkpoint, output, ctl, result, ierr)
    character(len=*), intent(in) :: checkpoint
    character(len=*), intent(in), optional :: output
    type(gran_run_control), intent(in), optional, target :: ctl
    type(gran_run_result), intent(out), optional, target :: result
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable, target :: cout(:), cck(:)
    type(c_ptr) :: pout, pctl, pres
    pout = c_null_ptr; pctl = c_null_ptr; pres = c_null_ptr
    call io_to_c(checkpoint, cck)
    if (present(output)) then
      call io_to_c(output, cout)
      pout = c_loc(cout)
    end if
    if (present(ctl)) pctl = c_loc(ctl)
    if (present(result)) pres = c_loc(result)
    call gran_check(c_gran_scene_resume(c_loc(cck), pout, pctl, pres), ierr)
  end subroutine gran_scene_resume

  ! ---- replicas and threads (src/io/run.cpp) ----
  !> Number of independent replicas of the scene's run and whether the output keeps their rows.
  subroutine gran_scene_set_replicas(scene, replicas, keep_replicas, ierr)
    type(c_ptr), intent(in) :: scene
    integer, intent(in) :: replicas
    logical, intent(in) :: keep_replicas
    integer, intent(out), optional :: ierr
    integer(c_int32_t) :: k
    k = 0
    if (keep_replicas) k = 1
    call gran_check(c_gran_scene_set_replicas(scene, int(replicas, c_int64_t), k), ierr)
  end subroutine gran_scene_set_replicas

  !> The scene's replicas and keep_replicas.
  subroutine gran_scene_replicas(scene, replicas, keep_replicas, ierr)
    type(c_ptr), intent(in) :: scene
    integer, intent(out) :: replicas
    logical, intent(out) :: keep_replicas
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: r
    integer(c_int32_t) :: k
    r = 0; k = 0
    call gran_check(c_gran_scene_replicas(scene, r, k), ierr)
    replicas = int(r)
    keep_replicas = k /= 0
  end subroutine gran_scene_replicas

  !> Threads for the replicas of a run (process-wide; 0: OMP_NUM_THREADS or all cores).
  subroutine gran_set_threads(nthreads, ierr)
    integer, intent(in) :: nthreads
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_set_threads(int(nthreads, c_int32_t)), ierr)
  end subroutine gran_set_threads

  !> Threads a run would use for its replicas.
  subroutine gran_get_threads(nthreads, ierr)
    integer, intent(out) :: nthreads
    integer, intent(out), optional :: ierr
    integer(c_int32_t) :: n
    n = 0
    call gran_check(c_gran_get_threads(n), ierr)
    nthreads = int(n)
  end subroutine gran_get_threads
  ! ---- GSRD wrappers ----
  subroutine gran_srd_options_default(opt, ierr)
    type(gran_srd_options), intent(out) :: opt
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_options_default(opt), ierr)
  end subroutine gran_srd_options_default

  subroutine gran_srd_create(opt, srd, ierr)
    type(gran_srd_options), intent(in) :: opt
    type(c_ptr), intent(out) :: srd
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_create(opt, srd), ierr)
  end subroutine gran_srd_create

  subroutine gran_srd_destroy(srd, ierr)
    type(c_ptr), intent(inout) :: srd
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_destroy(srd), ierr)
  end subroutine gran_srd_destroy

  subroutine gran_srd_advance(srd, steps, ierr)
    type(c_ptr), intent(in) :: srd
    integer(c_int64_t), intent(in) :: steps
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_advance(srd, steps), ierr)
  end subroutine gran_srd_advance

  subroutine gran_srd_observe(srd, obs, ierr)
    type(c_ptr), intent(in) :: srd
    type(gran_srd_obs), intent(out) :: obs
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_observe(srd, obs), ierr)
  end subroutine gran_srd_observe

  subroutine gran_srd_stress_reset(srd, ierr)
    type(c_ptr), intent(in) :: srd
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_stress_reset(srd), ierr)
  end subroutine gran_srd_stress_reset

  !> Borrowed views of the particle arrays (z, vz unassociated in 2-D).
  subroutine gran_srd_particles(srd, x, y, z, vx, vy, vz, ierr)
    type(c_ptr), intent(in) :: srd
    real(c_double), pointer, intent(out) :: x(:), y(:), z(:), vx(:), vy(:), vz(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: px, py, pz, pvx, pvy, pvz
    integer(c_int64_t) :: n
    integer :: e
    nullify(x, y, z, vx, vy, vz)
    e = c_gran_srd_particles(srd, n, px, py, pz, pvx, pvy, pvz)
    call gran_check(e, ierr)
    if (e /= 0) return
    call c_f_pointer(px, x, [n])
    call c_f_pointer(py, y, [n])
    call c_f_pointer(pvx, vx, [n])
    call c_f_pointer(pvy, vy, [n])
    if (c_associated(pz)) call c_f_pointer(pz, z, [n])
    if (c_associated(pvz)) call c_f_pointer(pvz, vz, [n])
  end subroutine gran_srd_particles

  subroutine gran_srd_structure_factor(srd, k, s, count, ierr)
    type(c_ptr), intent(in) :: srd
    real(c_double), intent(out) :: k(:), s(:)
    integer(c_int64_t), intent(out) :: count(:)
    integer, intent(out), optional :: ierr
    if (size(s) < size(k) .or. size(count) < size(k)) then
      call gran_check(c_gran_srd_structure_factor(srd, 0_c_int64_t, k, s, count), ierr)
      return
    end if
    call gran_check(c_gran_srd_structure_factor(srd, int(size(k), c_int64_t), k, s, count), ierr)
  end subroutine gran_srd_structure_factor

  !> GSRD velocity profile: mean of velocity component `component` (0-based, as in C) in
  !> size(mean) slabs along `axis` (0-based), and the particle count per slab.
  subroutine gran_srd_velocity_profile(srd, axis, component, mean, count, ierr)
    type(c_ptr), intent(in) :: srd
    integer, intent(in) :: axis, component
    real(c_double), intent(out) :: mean(:)
    integer(c_int64_t), intent(out) :: count(:)
    integer, intent(out), optional :: ierr
    if (size(count) < size(mean)) then
      call gran_check(c_gran_srd_velocity_profile(srd, int(axis, c_int32_t), int(component, c_int32_t), &
                                                  0_c_int64_t, mean, count), ierr)
      return
    end if
    call gran_check(c_gran_srd_velocity_profile(srd, int(axis, c_int32_t), int(component, c_int32_t), &
                                                int(size(mean), c_int64_t), mean, count), ierr)
  end subroutine gran_srd_velocity_profile

  !> The engine state as group `group` of the HDF5 file `path` (created if missing; the group replaced).
  subroutine gran_srd_checkpoint_write(srd, path, group, ierr)
    type(c_ptr), intent(in) :: srd
    character(len=*), intent(in) :: path, group
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable, target :: cp(:), cg(:)
    call io_to_c(path, cp)
    call io_to_c(group, cg)
    call gran_check(c_gran_srd_checkpoint_write(srd, c_loc(cp), c_loc(cg)), ierr)
  end subroutine gran_srd_checkpoint_write

  !> New engine from the state in group `group` of `path`.
  subroutine gran_srd_checkpoint_read(path, group, srd, ierr)
    character(len=*), intent(in) :: path, group
    type(c_ptr), intent(out) :: srd
    integer, intent(out), optional :: ierr
    character(kind=c_char), allocatable, target :: cp(:), cg(:)
    call io_to_c(path, cp)
    call io_to_c(group, cg)
    call gran_check(c_gran_srd_checkpoint_read(c_loc(cp), c_loc(cg), srd), ierr)
  end subroutine gran_srd_checkpoint_read

  !> Cell fields of the unshifted lattice (cells(1) x cells(2) (x cells(3)), x fastest):
  !> particles per cell, mean velocity (3, cells) and temperature. Each output is optional;
  !> a given one must hold at least the number of cells (velocity: 3 x cells), else GRAN_ERR_ARG.
  subroutine gran_srd_fields(srd, ncells, count, velocity, temperature, ierr)
    type(c_ptr), intent(in) :: srd
    integer(c_int64_t), intent(in) :: ncells
    real(c_double), intent(out), optional, target :: count(:), velocity(:, :), temperature(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pc, pv, pt
    pc = c_null_ptr; pv = c_null_ptr; pt = c_null_ptr
    if (present(count)) then
      if (size(count, kind=c_int64_t) < ncells) then
        call gran_core_shape_error('gran_srd_fields: count has fewer than ncells elements', ierr)
        return
      end if
      pc = c_loc(count)
    end if
    if (present(velocity)) then
      if (size(velocity, 1) /= 3 .or. size(velocity, 2, kind=c_int64_t) < ncells) then
        call gran_core_shape_error('gran_srd_fields: velocity must be (3, >= ncells)', ierr)
        return
      end if
      pv = c_loc(velocity)
    end if
    if (present(temperature)) then
      if (size(temperature, kind=c_int64_t) < ncells) then
        call gran_core_shape_error('gran_srd_fields: temperature has fewer than ncells elements', ierr)
        return
      end if
      pt = c_loc(temperature)
    end if
    call gran_check(c_gran_srd_fields(srd, pc, pv, pt), ierr)
  end subroutine gran_srd_fields
  ! ---- end GSRD wrappers ----

  ! ---- GSRD devices wrappers (CUDA backend) ----
  !> Move a GSRD run to another device (GRAN_SRD_DEVICE_*), state and RNG streams included.
  subroutine gran_srd_set_device(srd, device, ierr)
    type(c_ptr), intent(in) :: srd
    integer, intent(in) :: device
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_srd_set_device(srd, int(device, c_int32_t)), ierr)
  end subroutine gran_srd_set_device

  !> The device a GSRD run is on now (GRAN_SRD_DEVICE_CPU, _CUDA or _REFERENCE).
  subroutine gran_srd_get_device(srd, device, ierr)
    type(c_ptr), intent(in) :: srd
    integer, intent(out) :: device
    integer, intent(out), optional :: ierr
    integer(c_int32_t) :: d
    d = -1
    call gran_check(c_gran_srd_get_device(srd, d), ierr)
    device = int(d)
  end subroutine gran_srd_get_device
  ! ---- end GSRD devices wrappers ----
  ! ---- cell selector wrappers ----
  !> Defaults: 1 cell, dt 0 (set it), F_N 1, no aggregation, fragmentation or thermostat.
  subroutine gran_dsmc_cell_options_default(cell, ierr)
    type(gran_dsmc_cell_options), intent(out) :: cell
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_cell_options_default(cell), ierr)
  end subroutine gran_dsmc_cell_options_default

  !> New engine of the time-step/cell selector (as gran_dsmc_create, with the cell options).
  subroutine gran_dsmc_create_cell(sim, mix, opt, cell, counts, T0, ierr)
    type(c_ptr), intent(out) :: sim
    type(c_ptr), intent(in) :: mix
    type(gran_dsmc_options), intent(in) :: opt
    type(gran_dsmc_cell_options), intent(in) :: cell
    integer(c_int64_t), intent(in), target, contiguous, optional :: counts(:)
    real(c_double), intent(in), target, contiguous, optional :: T0(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pc, pt
    integer(c_int64_t) :: m
    sim = c_null_ptr
    pc = c_null_ptr
    pt = c_null_ptr
    m = -1
    if (c_gran_mixture_nspecies(mix, m) /= GRAN_SUCCESS) m = -1
    if (present(counts)) then
      if (m >= 0 .and. size(counts, kind=c_int64_t) /= m) then
        call gran_dsmc_shape_error('gran_dsmc_create_cell: size(counts) /= number of species', ierr)
        return
      end if
      if (size(counts) > 0) pc = c_loc(counts(1))
    end if
    if (present(T0)) then
      if (m >= 0 .and. size(T0, kind=c_int64_t) /= m) then
        call gran_dsmc_shape_error('gran_dsmc_create_cell: size(T0) /= number of species', ierr)
        return
      end if
      if (size(T0) > 0) pt = c_loc(T0(1))
    end if
    call gran_check(c_gran_dsmc_create_cell(mix, pc, pt, opt, cell, sim), ierr)
  end subroutine gran_dsmc_create_cell

  !> Steps done, box side, largest F_N (sigma g)_max dt / V_c of the last step.
  subroutine gran_dsmc_cell_info(sim, steps, box, pmax, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(out) :: steps
    real(c_double), intent(out) :: box, pmax
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_cell_info(sim, steps, box, pmax), ierr)
  end subroutine gran_dsmc_cell_info

  !> The [cell] table of a scene.
  subroutine gran_scene_dsmc_cell_options(scene, cell, ierr)
    type(c_ptr), intent(in) :: scene
    type(gran_dsmc_cell_options), intent(out) :: cell
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_dsmc_cell_options(scene, cell), ierr)
  end subroutine gran_scene_dsmc_cell_options
  !> Clusters, mass, sizes, merge / breakup / bounce counters and ledger parts (aggregating engines).
  subroutine gran_dsmc_get_cluster_stats(sim, st, ierr)
    type(c_ptr), intent(in) :: sim
    type(gran_dsmc_cluster_stats), intent(out) :: st
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_get_cluster_stats(sim, st), ierr)
  end subroutine gran_dsmc_get_cluster_stats

  !> Sparse size distribution: nsizes sizes present; sizes, counts (and T) filled when given (their
  !> size is the capacity: at least nsizes, else GRAN_ERR_RANGE).
  subroutine gran_dsmc_size_distribution(sim, nsizes, sizes, counts, T, ierr)
    type(c_ptr), intent(in) :: sim
    integer(c_int64_t), intent(out) :: nsizes
    integer(c_int64_t), intent(out), target, contiguous, optional :: sizes(:), counts(:)
    real(c_double), intent(out), target, contiguous, optional :: T(:)
    integer, intent(out), optional :: ierr
    integer(c_int64_t) :: cap
    type(c_ptr) :: ps, pc, pt
    cap = 0
    ps = c_null_ptr
    pc = c_null_ptr
    pt = c_null_ptr
    if (present(sizes) .neqv. present(counts)) then
      call gran_dsmc_shape_error('gran_dsmc_size_distribution: give both sizes and counts, or neither', ierr)
      return
    end if
    if (present(sizes)) then
      cap = min(size(sizes, kind=c_int64_t), size(counts, kind=c_int64_t))
      if (present(T)) cap = min(cap, size(T, kind=c_int64_t))
      if (cap > 0) then
        ps = c_loc(sizes(1))
        pc = c_loc(counts(1))
        if (present(T)) pt = c_loc(T(1))
      end if
    end if
    call gran_check(c_gran_dsmc_size_distribution(sim, cap, nsizes, ps, pc, pt), ierr)
  end subroutine gran_dsmc_size_distribution
  ! ---- end cell selector wrappers ----
  ! ---- aggregation in the event selectors: wrappers ----
  subroutine gran_dsmc_agg_options_default(agg, ierr)
    type(gran_dsmc_agg_options), intent(out) :: agg
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_dsmc_agg_options_default(agg), ierr)
  end subroutine gran_dsmc_agg_options_default

  !> New engine of an event selector with aggregation and fragmentation (as gran_dsmc_create).
  subroutine gran_dsmc_create_agg(sim, mix, opt, agg, counts, T0, ierr)
    type(c_ptr), intent(out) :: sim
    type(c_ptr), intent(in) :: mix
    type(gran_dsmc_options), intent(in) :: opt
    type(gran_dsmc_agg_options), intent(in) :: agg
    integer(c_int64_t), intent(in), target, contiguous, optional :: counts(:)
    real(c_double), intent(in), target, contiguous, optional :: T0(:)
    integer, intent(out), optional :: ierr
    type(c_ptr) :: pc, pt
    integer(c_int64_t) :: m
    character(len=64) :: bad
    sim = c_null_ptr
    pc = c_null_ptr
    pt = c_null_ptr
    bad = ''
    if (c_gran_mixture_nspecies(mix, m) /= GRAN_SUCCESS) m = -1
    if (present(counts)) then
      if (m >= 0 .and. size(counts, kind=c_int64_t) /= m) bad = 'counts'
      if (size(counts) > 0) pc = c_loc(counts(1))
    end if
    if (present(T0)) then
      if (m >= 0 .and. size(T0, kind=c_int64_t) /= m) bad = 'T0'
      if (size(T0) > 0) pt = c_loc(T0(1))
    end if
    if (len_trim(bad) > 0) then
      call gran_dsmc_shape_error('gran_dsmc_create_agg: size(' // trim(bad) // ') /= number of species', ierr)
      return
    end if
    call gran_check(c_gran_dsmc_create_agg(mix, pc, pt, opt, agg, sim), ierr)
  end subroutine gran_dsmc_create_agg

  !> The scene's aggregation and fragmentation ([aggregation], or the [cell] keys), any selector.
  subroutine gran_scene_dsmc_agg_options(scene, agg, ierr)
    type(c_ptr), intent(in) :: scene
    type(gran_dsmc_agg_options), intent(out) :: agg
    integer, intent(out), optional :: ierr
    call gran_check(c_gran_scene_dsmc_agg_options(scene, agg), ierr)
  end subroutine gran_scene_dsmc_agg_options
  ! ---- end aggregation in the event selectors: wrappers ----
end module granary
