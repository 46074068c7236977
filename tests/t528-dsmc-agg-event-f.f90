! t528-dsmc-agg-event-f.f90 - aggregation in the event selectors from Fortran: every wrapper of the
! block (gran_dsmc_agg_options_default, gran_dsmc_create_agg, gran_scene_dsmc_agg_options) with
! physics checks: in the low-rank and Bird selectors from monomers, every collision merges when
! e_agg is huge (mass kept, clusters = N - merges, no bounces) and, with e_frag = 0 and the binary
! law, every collision shatters into two pieces (clusters kept); the ledger closes to 1e-12;
! bad options return their code through ierr.
program t528_dsmc_agg_event_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix, sim, scene
  type(gran_dsmc_options) :: opt
  type(gran_dsmc_agg_options) :: agg, agg2
  type(gran_dsmc_cluster_stats) :: cst
  type(gran_dsmc_stats) :: st
  real(c_double) :: ek, e0, ed, nth(3, 2), ov(3, 2)
  integer(c_int64_t) :: value
  integer :: ierr, q
  integer(c_int32_t), parameter :: sel(2) = [GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD]
  real(c_double), parameter :: n = 0.01_c_double
  character(len=*), parameter :: text = &
    '[mixture]' // new_line('a') // 'nspecies = 2' // new_line('a') // 'm1 = 1.0' // new_line('a') // &
    'density = [0.01, 0.0]' // new_line('a') // '[restitution]' // new_line('a') // 'eps = 0.9' // new_line('a') // &
    '[engine]' // new_line('a') // 'selector = "bird"' // new_line('a') // 'counts = [500, 0]' // new_line('a') // &
    't_end = 1.0' // new_line('a') // '[aggregation]' // new_line('a') // 'e_agg = 0.5' // new_line('a') // &
    'frag_law = "binary"' // new_line('a')

  call gran_abi_query('sizeof(gran_dsmc_agg_options)', value)
  call expect(value == c_sizeof(agg), 'sizeof(gran_dsmc_agg_options)')
  call gran_dsmc_agg_options_default(agg)
  call expect(agg%e_agg == 0 .and. agg%e_frag > huge(1.0_c_double) .and. agg%eps_f == 1 .and. &
              agg%frag_law == GRAN_FRAG_MONOMERS, 'aggregation options default')

  call gran_mixture_create(mix, [n, 0.0_c_double, 0.0_c_double])
  call gran_mixture_set_restitution(mix, 0.9_c_double)
  call gran_dsmc_options_default(opt)
  opt%volume = 5000 / n
  do q = 1, 2
    opt%selector = sel(q)
    agg%e_agg = 1e12_c_double
    agg%e_frag = huge(1.0_c_double)
    agg%frag_law = GRAN_FRAG_MONOMERS
    call gran_dsmc_create_agg(sim, mix, opt, agg, T0=[1.0_c_double, 1.0_c_double, 1.0_c_double])
    call gran_dsmc_advance(sim, 50.0_c_double)
    call gran_dsmc_get_cluster_stats(sim, cst)
    call gran_dsmc_get_stats(sim, st)
    call expect(cst%mass == 5000 .and. cst%merges > 100 .and. cst%bounces == 0 .and. &
                cst%nclusters == 5000 - cst%merges .and. st%collisions == cst%merges, 'every collision merges')
    call gran_dsmc_energy(sim, ek, e0, ed)
    call expect(abs(ek - (e0 - ed)) <= 1e-12_c_double * e0, 'ledger closes (merges)')
    call gran_dsmc_destroy(sim)
    ! binary breakups only: the clusters stay 5000
    agg%e_agg = 0
    agg%e_frag = 0
    agg%frag_law = GRAN_FRAG_BINARY
    call gran_dsmc_create_agg(sim, mix, opt, agg, T0=[1.0_c_double, 1.0_c_double, 1.0_c_double])
    call gran_dsmc_advance_collisions(sim, 2000_c_int64_t)
    call gran_dsmc_get_cluster_stats(sim, cst)
    call expect(cst%mass == 5000 .and. cst%nclusters == 5000 .and. cst%breakups == 2000, 'binary breakups')
    call gran_dsmc_energy(sim, ek, e0, ed)
    call expect(abs(ek - (e0 - ed)) <= 1e-12_c_double * e0, 'ledger closes (breakups)')
    call gran_dsmc_destroy(sim)
  end do
  agg%eps_f = 2
  call gran_dsmc_create_agg(sim, mix, opt, agg, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG .and. .not. c_associated(sim), 'eps_f = 2 refused')
  agg%eps_f = 1
  call gran_dsmc_create_agg(sim, mix, opt, agg, T0=[1.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'wrong size of T0 refused')
  ! the kinetic theory of the binary law (gran_theory_aggregation_law through frag_law): mass with
  ! the overflow closes to 1e-12; a bad law is refused
  call gran_theory_aggregation(mix, [1.0_c_double, 1.0_c_double, 1.0_c_double], 1.0_c_double, 2.0_c_double, &
                               0.7_c_double, [10.0_c_double, 100.0_c_double], 1e-9_c_double, nth, overflow=ov, &
                               frag_law=GRAN_FRAG_BINARY)
  call expect(all(abs(nth(1, :) + 2 * nth(2, :) + 3 * nth(3, :) + ov(2, :) - n) <= 1e-12_c_double * n) .and. &
              ov(2, 2) > 0, 'binary law theory: mass closes')
  call gran_theory_aggregation(mix, [1.0_c_double, 1.0_c_double, 1.0_c_double], 1.0_c_double, 2.0_c_double, &
                               0.7_c_double, [10.0_c_double], 1e-9_c_double, nth(:, 1:1), ierr=ierr, frag_law=7_c_int32_t)
  call expect(ierr == GRAN_ERR_ARG, 'bad fragment law refused')
  call gran_mixture_destroy(mix)

  ! the [aggregation] table of a scene
  call gran_scene_parse(text, 'agg.toml', scene)
  call gran_scene_dsmc_agg_options(scene, agg2)
  call expect(agg2%e_agg == 0.5_c_double .and. agg2%frag_law == GRAN_FRAG_BINARY .and. &
              agg2%e_frag > huge(1.0_c_double), 'scene [aggregation] options')
  call gran_scene_destroy(scene)

  call test_finish('t528-dsmc-agg-event-f')
end program t528_dsmc_agg_event_f
