! t520-dsmc-cell-f.f90 - the time-step/cell selector from Fortran: every wrapper of the cell block
! (gran_dsmc_cell_options_default, gran_dsmc_create_cell, gran_dsmc_cell_info,
! gran_scene_dsmc_cell_options) with physics checks: an elastic gas keeps its energy and collides
! at the rate of the DSMC outline's Eq. 35 (4 standard errors), with the serial streams and with the
! streams by cell (the same state on 1 and 2 threads), positions lie in the box of side (F_N V)^(1/3),
! the steps done are t/dt; bad options return their code through ierr.
program t520_dsmc_cell_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix, sim, scene
  type(gran_dsmc_options) :: opt
  type(gran_dsmc_cell_options) :: cell, cell2
  type(gran_dsmc_stats) :: st
  type(gran_particles), pointer :: p
  real(c_double), pointer :: x(:)
  real(c_double) :: box, pmax, ek, e0, ed, expect_c
  integer(c_int64_t) :: steps, value, ns
  integer(c_int64_t), allocatable :: sz(:), cn(:)
  real(c_double), allocatable :: tk(:)
  type(gran_dsmc_cluster_stats) :: cst
  integer :: ierr
  real(c_double), parameter :: pi = 3.14159265358979323846_c_double, n = 0.01_c_double
  character(len=*), parameter :: text = &
    '[mixture]' // new_line('a') // 'nspecies = 1' // new_line('a') // 'density = [0.01]' // new_line('a') // &
    '[restitution]' // new_line('a') // 'eps = 0.9' // new_line('a') // &
    '[engine]' // new_line('a') // 'selector = "cell"' // new_line('a') // 'counts = [500]' // new_line('a') // &
    't_end = 1.0' // new_line('a') // '[cell]' // new_line('a') // 'cells = 2' // new_line('a') // &
    'dt = 0.25' // new_line('a') // 'e_agg = 0.5' // new_line('a')
  character(len=*), parameter :: text2 = &
    '[mixture]' // new_line('a') // 'nspecies = 1' // new_line('a') // 'density = [0.01]' // new_line('a') // &
    '[restitution]' // new_line('a') // 'eps = 0.9' // new_line('a') // &
    '[engine]' // new_line('a') // 'selector = "cell"' // new_line('a') // 'counts = [500]' // new_line('a') // &
    't_end = 1.0' // new_line('a') // '[cell]' // new_line('a') // 'dt = 0.25' // new_line('a') // &
    'streams = "cells"' // new_line('a')

  call gran_abi_query('sizeof(gran_dsmc_cell_options)', value)
  call expect(value == c_sizeof(cell), 'sizeof(gran_dsmc_cell_options)')
  call gran_abi_query('GRAN_SELECTOR_CELL', value)
  call expect(value == GRAN_SELECTOR_CELL, 'GRAN_SELECTOR_CELL')

  call gran_mixture_create(mix, [n])
  call gran_mixture_set_restitution(mix, 1.0_c_double)
  call gran_dsmc_options_default(opt)
  opt%volume = 10000 / n
  opt%seed = 9
  call gran_dsmc_cell_options_default(cell)
  call expect(cell%cells == 1 .and. cell%dt == 0 .and. cell%fn == 1 .and. cell%e_agg == 0 .and. &
              cell%e_frag > huge(1.0_c_double) .and. cell%placement == GRAN_PLACE_RANDOM, 'cell options default')
  ! dt not set: refused
  call gran_dsmc_create_cell(sim, mix, opt, cell, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG .and. .not. c_associated(sim), 'dt = 0 refused')
  cell%dt = 2
  cell%cells = 3
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double, 2.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'wrong size of T0 refused')
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double])
  call gran_dsmc_advance(sim, 300.0_c_double)
  call gran_dsmc_cell_info(sim, steps, box, pmax)
  call expect(steps == 150, 'steps = t / dt')
  call expect(abs(box - (10000 / n)**(1.0_c_double / 3)) < 1e-9_c_double * box, 'box side (F_N V)^(1/3)')
  call expect(pmax > 0 .and. pmax < 2, 'F_N (sigma g)_max dt / V_c of the last step in (0, 2)')
  call gran_dsmc_particles(sim, p)
  call c_f_pointer(p%x, x, [3 * p%n])
  call expect(all(x >= 0 .and. x < box), 'positions in the box')
  call gran_dsmc_energy(sim, ek, e0, ed)
  call expect(abs(ek - e0) <= 1e-12_c_double * e0, 'elastic: energy kept')
  call gran_dsmc_get_stats(sim, st)
  expect_c = 0.5_c_double * 10000 * 4 * sqrt(pi) * n * 300   ! Eq. 35 at T = 1
  call expect(abs(st%collisions - expect_c) < 4 * sqrt(expect_c), 'collisions against Eq. 35')
  call gran_dsmc_destroy(sim)

  ! streams by cell on every thread: the same physics, and the same state whatever the threads
  cell%streams = GRAN_CELL_STREAMS_CELLS
  call gran_set_threads(2)
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double])
  call gran_dsmc_advance(sim, 300.0_c_double)
  call gran_dsmc_energy(sim, ek, e0, ed)
  call expect(abs(ek - e0) <= 1e-12_c_double * e0, 'streams by cell, elastic: energy kept')
  call gran_dsmc_get_stats(sim, st)
  call expect(abs(st%collisions - expect_c) < 4 * sqrt(expect_c), 'streams by cell: collisions against Eq. 35')
  value = st%collisions
  call gran_dsmc_destroy(sim)
  call gran_set_threads(1)
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double])
  call gran_dsmc_advance(sim, 300.0_c_double)
  call gran_dsmc_energy(sim, ed, e0, pmax)
  call gran_dsmc_get_stats(sim, st)
  call expect(st%collisions == value .and. ed == ek, 'streams by cell: 1 thread as 2 threads')
  call gran_dsmc_destroy(sim)
  call gran_set_threads(0)
  cell%streams = 9
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG .and. .not. c_associated(sim), 'streams = 9 refused')
  cell%streams = GRAN_CELL_STREAMS_SERIAL

  ! the [cell] table of a scene
  call gran_scene_parse(text, 'cell.toml', scene)
  call gran_scene_dsmc_cell_options(scene, cell2)
  call expect(cell2%cells == 2 .and. cell2%dt == 0.25_c_double .and. cell2%e_agg == 0.5_c_double, &
              'scene [cell] options')
  call gran_scene_destroy(scene)
  call gran_scene_parse(text2, 'cell2.toml', scene)
  call gran_scene_dsmc_cell_options(scene, cell2)
  call expect(cell2%streams == GRAN_CELL_STREAMS_CELLS, 'scene [cell] streams = "cells"')
  call gran_scene_destroy(scene)
  ! aggregation: k-mer mixture, every collision merges (e_agg huge)
  call gran_mixture_destroy(mix)
  call gran_mixture_create(mix, [n, 0.0_c_double, 0.0_c_double])
  call gran_mixture_set_restitution(mix, 0.9_c_double)
  call gran_dsmc_cell_options_default(cell)
  cell%dt = 0.5_c_double
  cell%e_agg = 1e12_c_double
  opt%volume = 5000 / n
  call gran_dsmc_create_cell(sim, mix, opt, cell, T0=[1.0_c_double, 1.0_c_double, 1.0_c_double])
  call gran_dsmc_advance(sim, 50.0_c_double)
  call gran_dsmc_get_cluster_stats(sim, cst)
  call expect(cst%mass == 5000 .and. cst%merges > 100 .and. cst%bounces == 0 .and. &
              cst%nclusters == 5000 - cst%merges, 'every collision merges, mass kept')
  call gran_dsmc_size_distribution(sim, ns)
  call expect(ns == cst%nsizes .and. ns >= 2, 'number of sizes present')
  allocate(sz(ns), cn(ns), tk(ns))
  call gran_dsmc_size_distribution(sim, ns, sz, cn, tk)
  call expect(sum(sz * cn) == 5000 .and. sum(cn) == cst%nclusters .and. sz(1) == 1 .and. all(tk >= 0), &
              'sparse size distribution holds every cluster')
  call gran_dsmc_size_distribution(sim, ns, sz(1:1), cn(1:1), ierr=ierr)
  call expect(ierr == GRAN_ERR_RANGE .or. ns == 1, 'too small a capacity refused')
  call gran_dsmc_destroy(sim)
  deallocate(sz, cn, tk)
  call gran_dsmc_cell_info(c_null_ptr, steps, box, pmax, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'info of a NULL engine refused')
  call gran_mixture_destroy(mix)

  call test_finish('t520-dsmc-cell-f')
end program t520_dsmc_cell_f
