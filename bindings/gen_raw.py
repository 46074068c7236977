#!/usr/bin/env python3
"""gen_raw.py - the raw layer of the Fortran bindings, generated from include/granary.h.

    python3 bindings/gen_raw.py           write the generated files (run from the repository root
                                          or anywhere: paths are relative to this script)
    python3 bindings/gen_raw.py --check   exit 1, naming the stale files, when a committed file
                                          differs from what the current header gives
    python3 bindings/gen_raw.py --release mark the manifest's ABI as released (the release step:
                                          from then on it may only grow)

The model is FFTW's api/genf03.pl: the C declarations are parsed, a type table maps each C type to
its Fortran kind, and a few annotations (the table ANNOTATIONS below) say what a pointer parameter
is where the default rule does not. Three files come out of one parse:

  bindings/granary_raw.inc   included by bindings/granary.f90 (module granary): every integer
                             constant (enums, error codes, version), every plain struct as a
                             bind(C) derived type, and one bind(C) interface `c_<name>` per public
                             function. The idiomatic wrappers of granary.f90 call these.
  src/core/abi_table.inc     the X-macro list of gran_abi_query: sizeof of every struct, offsetof
                             of every field, the value of every constant.
  include/granary.abi        the ABI manifest: one line per constant (with its value), struct
                             (every field with its type, in order) and function (its prototype),
                             headed by `abi GRAN_ABI_VERSION released|unreleased`. Once an ABI
                             is released (--release), a change that can break a program built
                             against it (a line gone or changed) under the same number is
                             refused and nothing is written (docs/developers/abi.md).
  tests/t901-layout-f.inc    t901-layout-f's side: the same names from the Fortran mirrors
                             (c_sizeof, c_loc differences, the parameters), compared with
                             gran_abi_query.
The C side of t901 (tests/t901-layout.c) includes src/core/abi_table.inc with its own macros.

Default rules for a parameter (C -> Fortran dummy argument):
  T x                      T, value                              (numbers, handles by value)
  const T *x  / T *x       T, intent(in) :: x(*) / intent(out) :: x(*)   (T a number)
  T x[N]                   the same with x(N)
  const S *x  / S *x       type(S), intent(in) :: x / intent(inout) :: x (S a plain struct)
  [const] H *h             type(c_ptr), value :: h               (H an opaque handle)
  F f                      type(c_funptr), value :: f            (F a function-pointer typedef)
  H **h, [const] T **p     type(c_ptr), intent(out) :: h; intent(inout) in *_destroy
  const char *s / char *s  character(kind=c_char), intent(in) :: s(*) / intent(out) :: s(*)
  void *p                  type(c_ptr), value :: p
Annotations (ANNOTATIONS, `function param=kind ...`):
  out / inout / in         a scalar the function writes / reads and writes / reads
  null                     may be NULL: type(c_ptr), value (the wrapper passes c_loc(x) or
                           c_null_ptr)
  ptr                      an address passed as type(c_ptr), value (the wrapper passes c_loc of
                           a buffer of its own)
  len=N                    an array of fixed length N
  array                    an array of any length (x(*)), for a struct pointer
Initial values of the derived types' components (what a Fortran variable holds before the
library's *_default fills it) are in FIELD_INIT; a component not named there starts at 0
(c_null_ptr, c_null_funptr). Python 3 standard library only.
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = 'include/granary.h'
OUT_RAW = 'bindings/granary_raw.inc'
OUT_ABI = 'src/core/abi_table.inc'
OUT_T901 = 'tests/t901-layout-f.inc'
OUT_MANIFEST = 'include/granary.abi'
REGEN = 'python3 bindings/gen_raw.py'

# ---- type table: C scalar type -> Fortran type -----------------------------------------------
NUMERIC = {
    'int': 'integer(c_int)',
    'int32_t': 'integer(c_int32_t)',
    'int64_t': 'integer(c_int64_t)',
    'uint64_t': 'integer(c_int64_t)',  # the bits of the uint64_t
    'double': 'real(c_double)',
    'size_t': 'integer(c_size_t)',
    'char': 'character(kind=c_char)',
}

# ---- annotations of pointer parameters where the default rule does not hold -------------------
ANNOTATIONS = """
gran_get_version          major=out minor=out patch=out
gran_cuda_compiled        compiled=out
gran_cuda_device_count    count=out
gran_warning_count        count=out
gran_rng_seed             rng=inout
gran_cuda_rng_uniform     states=array
gran_segtree_get          w=out
gran_segtree_total        total=out
gran_segtree_sample       index=out
gran_particles_add        index=out
gran_particles_memory     bytes=out
gran_abi_query            value=out
gran_mixture_create       mass=null sigma=null
gran_mixture_nspecies     nspecies=out
gran_mixture_get          mass=null sigma=null density=null
gran_mixture_restitution_model  model=out
gran_mixture_pair         eps=null beta=null g2=null
gran_viscoelastic_eps     eps=out
gran_viscoelastic_eps_vn  eps=out
gran_theory_collision_rate1  inv_tau_c=out
gran_theory_hcs           tau0=out
gran_theory_hcs_approx    tau0=out
gran_theory_hcs_sonine2   tau0=out
gran_theory_hcs_sonine_n  tau0=out
gran_theory_msd_hcs       msd_total=null
gran_theory_msd           msd_total=null
gran_theory_msd_hcs_approx  msd_total=null
gran_theory_msd_approx    msd_total=null
gran_theory_msd_sonine    a20=null msd_total=null
gran_theory_msd_sonine2   a20=null a30=null msd_total=null
gran_theory_temperatures_sonine2  a20=null a30=null a2=null a3=null
gran_theory_temperatures_driven  heating=null
gran_theory_tamsd_parts   delta0=null xi=null
gran_theory_msd_mono      tau0=out
gran_theory_agg_fractions f_stick=out f_frag=out
gran_theory_tracer_gamma_approx  gamma=out
gran_theory_tracer_tau_v_hat     tau_v_hat=out
gran_theory_aggregation   T=null overflow=null
gran_theory_aggregation_law  T=null overflow=null
gran_theory_smoluchowski_constant  overflow=null
gran_dsmc_options_default opt=out
gran_dsmc_create          counts=null T0=null
gran_dsmc_time            t=out
gran_dsmc_get_stats       stats=out
gran_dsmc_msd             msd=null msd_total=null
gran_dsmc_energy          e_kin=null e_initial=null e_dissipated=null
gran_dsmc_trajectories    ntraj=out nsamples=out
gran_dsmc_cell_options_default  cell=out
gran_dsmc_create_cell     counts=null T0=null
gran_dsmc_cell_info       steps=out box=out pmax=out
gran_dsmc_get_cluster_stats  st=out
gran_dsmc_size_distribution  nsizes=out sizes=null counts=null T=null
gran_dsmc_agg_options_default  agg=out
gran_dsmc_create_agg      counts=null T0=null
gran_sonine_a2            a2=out mass=null
gran_speed_histogram      nbeyond=out
gran_scene_sizes          nspecies=out ntimes=out nlags=out t_start=out t_end=out
gran_scene_initial_temperatures  tau0=out
gran_scene_dsmc_options   opt=ptr have_counts=out
gran_scene_dsmc_cell_options  cell=out
gran_scene_dsmc_agg_options   agg=out
gran_scene_run            output=null checkpoint=null ctl=null result=null
gran_scene_resume         checkpoint=ptr output=null ctl=null result=null
gran_scene_replicas       replicas=out keep_replicas=out
gran_get_threads          nthreads=out
gran_srd_options_default  opt=out
gran_srd_observe          obs=out
gran_srd_particles        n=out
gran_srd_checkpoint_write path=ptr group=ptr
gran_srd_checkpoint_read  path=ptr group=ptr
gran_srd_fields           count=null velocity=null temperature=null
gran_srd_get_device       device=out
"""

# ---- initial values of derived-type components (Fortran side; the C defaults are the library's
# *_default functions). None: no initial value. A struct mapped to None has none at all. --------
FIELD_INIT = {
    'gran_rng': None,
    'gran_segtree': {'m': None, 'base': None, 'nupdate': None},
    'gran_dsmc_options': {'seed': '1', 'traj_dt': '1', 'speed_classes': '-1'},
    'gran_dsmc_cell_options': {'cells': '1', 'fn': '1', 'e_frag': 'huge(1.0_c_double)', 'eps_f': '1',
                               'bath_mass': '1', 'bath_T': '1', 'bath_sigma': '1'},
    'gran_dsmc_agg_options': {'e_frag': 'huge(1.0_c_double)', 'eps_f': '1'},
    'gran_srd_options': {'dim': '3', 'wall_axis': '-1', 'wall_rule': '1', 'cells': '16', 'a': '1',
                         'n0': '10', 'dt': '1', 'alpha_deg': '130', 'eps': '1', 'T0': '1', 'seed': '1',
                         'sort_every': '50'},
}


# public functions without a wrapper of their own in granary.f90 (no note about them)
# constants the manifest lists elsewhere or not at all: the release version (the ABI number, its
# `abi` line, says what is compatible)
ABI_FREE = {'GRAN_VERSION_MAJOR', 'GRAN_VERSION_MINOR', 'GRAN_VERSION_PATCH', 'GRAN_ABI_VERSION'}

NOT_WRAPPED = {
    'gran_last_error_message',  # gran_last_error_message() of the module copies with gran_last_error_copy
}


class GenError(Exception):
    pass


# ---- parsing ------------------------------------------------------------------------------------
def strip_comments(text):
    text = re.sub(r'/\*.*?\*/', lambda m: '\n' * m.group(0).count('\n'), text, flags=re.S)
    return re.sub(r'//[^\n]*', '', text)


def parse_header(text):
    """Constants, structs, opaque handles, function-pointer types and prototypes of the header."""
    consts = []  # (name, value)
    for name in ('VERSION_MAJOR', 'VERSION_MINOR', 'VERSION_PATCH', 'ABI_VERSION'):
        m = re.search(r'^#define (GRAN_%s) (-?\d+)\s*$' % name, text, re.M)
        if not m:
            raise GenError('%s: no #define GRAN_%s' % (HEADER, name))
        consts.append((m.group(1), int(m.group(2))))
    m = re.search(r'#define GRAN_ERROR_LIST\(X\)(.*?)\n\s*\n', text, re.S)
    if not m:
        raise GenError('%s: no GRAN_ERROR_LIST' % HEADER)
    errors = re.findall(r'X\((GRAN_\w+),\s*(-?\d+),', m.group(1))
    if not errors:
        raise GenError('%s: GRAN_ERROR_LIST has no entries' % HEADER)
    consts += [(n, int(v)) for n, v in errors]

    code = strip_comments(text)
    # preprocessor lines (with their continuations) out
    code = re.sub(r'^[ \t]*#(?:[^\n]*\\\n)*[^\n]*', '', code, flags=re.M)
    structs, opaque, funptrs, funcs = [], set(), set(), []
    for stmt in split_statements(code):
        s = ' '.join(stmt.split())
        if not s:
            continue
        m = re.match(r'enum(?: (\w+))? \{(.*)\}$', s)
        if m:
            if m.group(1) == 'gran_error':  # the X-macro list, read above
                continue
            value = -1
            for item in [i.strip() for i in m.group(2).split(',') if i.strip()]:
                mm = re.match(r'(\w+)(?: = (-?\d+))?$', item)
                if not mm:
                    raise GenError('%s: enum %s: cannot read "%s"' % (HEADER, m.group(1), item))
                value = int(mm.group(2)) if mm.group(2) is not None else value + 1
                consts.append((mm.group(1), value))
            continue
        m = re.match(r'typedef struct (\w+) \{(.*)\} (\w+)$', s)
        if m:
            if m.group(1) != m.group(3):
                raise GenError('%s: typedef struct %s ... %s: names differ' % (HEADER, m.group(1), m.group(3)))
            structs.append((m.group(1), parse_fields(m.group(1), m.group(2))))
            continue
        m = re.match(r'typedef struct (\w+) (\w+)$', s)
        if m:
            opaque.add(m.group(2))
            continue
        m = re.match(r'typedef int \(\*(\w+)\)\(.*\)$', s)
        if m:
            funptrs.add(m.group(1))
            continue
        m = re.match(r'GRAN_EXTERN (.+?)(\w+)\((.*)\)$', s)
        if m:
            funcs.append((m.group(2), m.group(1).strip(), parse_params(m.group(2), m.group(3))))
            continue
        raise GenError('%s: cannot read the declaration "%s"' % (HEADER, s[:100]))
    names = [n for n, _ in consts]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise GenError('%s: constants defined twice: %s' % (HEADER, ', '.join(dup)))
    consts = [(n, v) for n, v in consts if not n.endswith('_')]
    return consts, structs, opaque, funptrs, funcs


def split_statements(code):
    """Top-level declarations, split at ';' outside braces."""
    out, depth, cur = [], 0, []
    for ch in code:
        if ch == '{':
            depth += 1
        elif ch == '}':
            depth -= 1
        if ch == ';' and depth == 0:
            out.append(''.join(cur))
            cur = []
        else:
            cur.append(ch)
    if ''.join(cur).strip():
        raise GenError('%s: text after the last declaration: "%s"' % (HEADER, ''.join(cur).strip()[:80]))
    return out


def parse_decl(text, where):
    """`[const] type [*...] name [[N]]` -> its parts."""
    m = re.match(r'^(.*?)\s*\[(\d+)\]$', text.strip())
    length = int(m.group(2)) if m else None
    body = m.group(1) if m else text
    tokens = body.replace('*', ' * ').split()
    const = bool(tokens) and tokens[0] == 'const'
    if const:
        tokens = tokens[1:]
    if len(tokens) < 2 or any(t != '*' for t in tokens[1:-1]) or not re.match(r'\w+$', tokens[0]) \
            or not re.match(r'[A-Za-z_]\w*$', tokens[-1]):
        raise GenError('%s: %s: cannot read "%s"' % (HEADER, where, text.strip()))
    return {'const': const, 'type': tokens[0], 'ptr': len(tokens) - 2, 'name': tokens[-1], 'len': length}


def parse_fields(struct, body):
    fields = []
    for stmt in [x.strip() for x in body.split(';') if x.strip()]:
        m = re.match(r'((?:const )?\w+)\s+(.*)$', stmt)
        if not m:
            raise GenError('%s: struct %s: cannot read "%s"' % (HEADER, struct, stmt))
        for d in m.group(2).split(','):
            fields.append(parse_decl(m.group(1) + ' ' + d.strip(), 'struct ' + struct))
    return fields


def parse_params(func, text):
    text = text.strip()
    if text in ('', 'void'):
        return []
    return [parse_decl(p.strip(), func) for p in text.split(',')]


def parse_annotations():
    ann = {}
    for line in ANNOTATIONS.strip().splitlines():
        words = line.split()
        if not words:
            continue
        func = words[0]
        if func in ann:
            raise GenError('gen_raw.py: ANNOTATIONS: %s listed twice' % func)
        ann[func] = {}
        for w in words[1:]:
            p, _, kind = w.partition('=')
            if not (kind in ('out', 'inout', 'in', 'null', 'ptr', 'array') or re.match(r'len=\d+$', kind)):
                raise GenError('gen_raw.py: ANNOTATIONS: %s %s: unknown kind "%s"' % (func, p, kind))
            ann[func][p] = kind
    return ann


# ---- Fortran ----------------------------------------------------------------------------------
def fortran_scalar(ctype, ctx):
    if ctype in NUMERIC:
        return NUMERIC[ctype]
    raise GenError('%s: %s: no Fortran type for C type "%s" (add it to NUMERIC in gen_raw.py)' % (HEADER, ctx, ctype))


def field_decl(struct, f, structs, funptrs):
    where = 'struct %s field %s' % (struct, f['name'])
    if f['type'] in funptrs and f['ptr'] == 0:
        return 'type(c_funptr)', 'c_null_funptr'
    if f['ptr'] > 0:
        return 'type(c_ptr)', 'c_null_ptr'
    if f['type'] in structs:
        raise GenError('%s: %s: nested structs are not mirrored yet' % (HEADER, where))
    t = fortran_scalar(f['type'], where)
    return t, ('0.0_c_double' if t == 'real(c_double)' else '0')


def param_decl(func, p, ann, structs, opaque, funptrs):
    """(Fortran type and attributes, dimension suffix) of a parameter."""
    kind = ann.get(p['name'])
    where = '%s(%s)' % (func, p['name'])
    t, ptr, const = p['type'], p['ptr'], p['const']
    if t in funptrs and ptr == 0 and p['len'] is None and kind is None:
        return 'type(c_funptr), value', ''
    if kind in ('null', 'ptr'):
        if ptr == 0 and p['len'] is None:
            raise GenError('%s: %s is not a pointer (annotation %s)' % (HEADER, where, kind))
        return 'type(c_ptr), value', ''
    if p['len'] is not None:
        ptr += 1
    if ptr == 0:
        if t in structs:
            raise GenError('%s: %s: structs by value are not mirrored' % (HEADER, where))
        return fortran_scalar(t, where) + ', value', ''
    if ptr >= 2:
        return 'type(c_ptr), intent(%s)' % ('inout' if func.endswith('_destroy') else 'out'), ''
    if t in opaque:
        return 'type(c_ptr), value', ''
    if t == 'void':
        return 'type(c_ptr), value', ''
    if t in structs:
        base = 'type(%s)' % t
        default_intent = 'in' if const else 'inout'
    else:
        base = fortran_scalar(t, where)
        default_intent = 'in' if const else 'out'
    length = p['len']
    if kind and kind.startswith('len='):
        length = int(kind[4:])
    if kind in ('out', 'inout', 'in'):
        if const and kind != 'in':
            raise GenError('%s: %s is const but annotated %s' % (HEADER, where, kind))
        return '%s, intent(%s)' % (base, kind), ''
    if t in structs and kind != 'array' and length is None:
        return '%s, intent(%s)' % (base, default_intent), ''
    return '%s, intent(%s)' % (base, default_intent), '(%s)' % (length if length is not None else '*')


def fortran_names(names, reserved):
    """Fortran is case-insensitive: a name equal to an earlier one but for case gets a suffix."""
    seen, out = set(r.lower() for r in reserved), []
    for n in names:
        m = n
        while m.lower() in seen:
            m += '_'
        seen.add(m.lower())
        out.append(m)
    return out


def wrap_call(head, args, tail, indent, cont_indent):
    """`head(args) tail` on lines of at most 110 columns, with & continuations."""
    line = '%s%s(%s)%s' % (indent, head, ', '.join(args), tail)
    if len(line) <= 110:
        return [line]
    lines, cur = [], '%s%s(' % (indent, head)
    for i, a in enumerate(args):
        piece = a + (', ' if i < len(args) - 1 else ')')
        if len(cur) + len(piece) > 108 and cur.strip()[-1] != '(':
            lines.append(cur.rstrip() + ' &')
            cur = cont_indent
        cur += piece
    if len(cur) + len(tail) > 108:
        lines.append(cur + ' &')
        lines.append(cont_indent + tail.strip())
    else:
        lines.append(cur + tail)
    return lines


def gen_raw(consts, structs, opaque, funptrs, funcs, ann):
    struct_map = dict(structs)
    L = ['! granary_raw.inc - GENERATED from include/granary.h by bindings/gen_raw.py: do not edit.',
         '! Regenerate with `%s` after changing the header (make checks it).' % REGEN,
         '! Included by bindings/granary.f90 (module granary): the integer constants, the plain structs',
         '! as bind(C) types (components as in the header; initial values from FIELD_INIT of',
         '! gen_raw.py) and one raw interface c_<name> per public function (private; the wrappers of',
         '! granary.f90 call them). The header documents every field, parameter and value.',
         '',
         '  ! ---- constants ----']
    for n, v in consts:
        L.append('  integer(c_int), parameter, public :: %s = %d' % (n, v))
    L.append('')
    L.append('  ! ---- plain structs ----')
    for name, fields in structs:
        init = FIELD_INIT.get(name, {})
        names = [f['name'] for f in fields]
        if init is not None:
            unknown = sorted(set(init) - set(names))
            if unknown:
                raise GenError('gen_raw.py: FIELD_INIT[%s] names no field %s' % (name, ', '.join(unknown)))
        if len(set(n.lower() for n in names)) != len(names):
            raise GenError('%s: struct %s: field names equal but for case' % (HEADER, name))
        L.append('  type, bind(C), public :: %s' % name)
        for f in fields:
            t, zero = field_decl(name, f, struct_map, funptrs)
            dim = '(%d)' % f['len'] if f['len'] else ''
            val = None if init is None else init.get(f['name'], zero)
            L.append('    %s :: %s%s%s' % (t, f['name'], dim, '' if val is None else ' = ' + val))
        L.append('  end type %s' % name)
    L.append('')
    L.append('  ! ---- raw interfaces: one per public function ----')
    L.append('  interface')
    for fname, ret, params in funcs:
        a = ann.get(fname, {})
        pnames = [p['name'] for p in params]
        unknown = sorted(set(a) - set(pnames))
        if unknown:
            raise GenError('gen_raw.py: ANNOTATIONS: %s has no parameter %s' % (fname, ', '.join(unknown)))
        if ret == 'int':
            rtype, rname = 'integer(c_int)', 'ierr'
        elif ret in ('const char *', 'const char*'):
            rtype, rname = 'type(c_ptr)', 'str'
        else:
            raise GenError('%s: %s returns "%s" (int or const char * only)' % (HEADER, fname, ret))
        fn = fortran_names(pnames, [rname, 'c_' + fname])
        decls = [param_decl(fname, p, a, struct_map, opaque, funptrs) for p in params]
        imports = set()
        for t, _ in decls + [(rtype, '')]:
            imports.update(re.findall(r'\b(c_\w+)\b', t))
            imports.update(re.findall(r'type\((gran_\w+)\)', t))
        imports = sorted(i for i in imports if i.startswith('c_')) + sorted(i for i in imports if i.startswith('gran_'))
        L += wrap_call('function c_' + fname, fn, " bind(C, name='%s') result(%s)" % (fname, rname),
                       '    ', '        ')
        L.append('      import :: ' + ', '.join(imports))
        for (t, dim), n in zip(decls, fn):
            L.append('      %s :: %s%s' % (t, n, dim))
        L.append('      %s :: %s' % (rtype, rname))
        L.append('    end function c_' + fname)
    L.append('  end interface')
    return '\n'.join(L) + '\n'


def gen_abi(consts, structs):
    L = ['/* abi_table.inc - GENERATED from include/granary.h by bindings/gen_raw.py: do not edit.',
         ' * Regenerate with `%s` (make checks that it is current).' % REGEN,
         ' * The names gran_abi_query answers: GRAN_ABI_SIZE(struct), GRAN_ABI_OFFSET(struct, field),',
         ' * GRAN_ABI_CONST(name); the includer defines the three macros (src/core/abi.cpp,',
         ' * tests/t901-layout.c). */']
    for name, fields in structs:
        L.append('GRAN_ABI_SIZE(%s)' % name)
        for f in fields:
            L.append('GRAN_ABI_OFFSET(%s, %s)' % (name, f['name']))
    for n, _ in consts:
        L.append('GRAN_ABI_CONST(%s)' % n)
    return '\n'.join(L) + '\n'


def c_decl(d):
    """A parsed declaration back in canonical C."""
    return '%s%s %s%s%s' % ('const ' if d['const'] else '', d['type'], '*' * d['ptr'], d['name'],
                            '[%d]' % d['len'] if d['len'] is not None else '')


def gen_manifest(consts, structs, opaque, funptrs, funcs, status):
    abi = dict(consts)['GRAN_ABI_VERSION']
    L = ['# granary.abi - GENERATED from include/granary.h by bindings/gen_raw.py: do not edit.',
         '# The public ABI of libgranary.so.%d: what a program built against this header relies on.' % abi,
         '# Once released, a line that goes or changes needs a higher GRAN_ABI_VERSION (docs/developers/abi.md).',
         'abi %d %s' % (abi, status)]
    L += ['const %s %d' % (n, v) for n, v in consts if n not in ABI_FREE]
    L += ['opaque %s' % n for n in sorted(opaque)]
    L += ['callback %s' % n for n in sorted(funptrs)]
    L += ['struct %s { %s; }' % (name, '; '.join(c_decl(f) for f in fields)) for name, fields in structs]
    L += ['function %s %s(%s)' % (ret, name, ', '.join(c_decl(p) for p in params) or 'void')
          for name, ret, params in funcs]
    return '\n'.join(L) + '\n'


def manifest_parts(text):
    """(ABI number, 'released' or 'unreleased', the other lines) of a manifest."""
    lines = [x for x in text.splitlines() if x and not x.startswith('#')]
    m = re.match(r'abi (\d+) (released|unreleased)$', lines[0]) if lines else None
    if not m:
        raise GenError('%s: the first line is not "abi N released|unreleased"' % OUT_MANIFEST)
    return int(m.group(1)), m.group(2), lines[1:]


def gen_t901(consts, structs):
    L = ['! t901-layout-f.inc - GENERATED from include/granary.h by bindings/gen_raw.py: do not edit.',
         '! Regenerate with `%s`. Included after `contains` by tests/t901-layout-f.f90, which' % REGEN,
         '! supplies check(name, fortran_value) and offset(field, struct) (c_size_t): every struct size,',
         '! field offset and constant of the module granary by its gran_abi_query name.',
         '  subroutine check_all_generated()']
    for i, (name, _) in enumerate(structs):
        L.append('    type(%s), target :: s%d' % (name, i))
    for i, (name, fields) in enumerate(structs):
        L.append('    call check(\'sizeof(%s)\', c_sizeof(s%d))' % (name, i))
        for f in fields:
            L.append('    call check(\'offsetof(%s, %s)\', offset(c_loc(s%d%%%s), c_loc(s%d)))'
                     % (name, f['name'], i, f['name'], i))
    for n, _ in consts:
        L.append('    call check(\'%s\', int(%s, c_size_t))' % (n, n))
    L.append('  end subroutine check_all_generated')
    return '\n'.join(L) + '\n'


def generate():
    with open(os.path.join(ROOT, HEADER)) as f:
        text = f.read()
    consts, structs, opaque, funptrs, funcs = parse_header(text)
    ann = parse_annotations()
    names = {f[0] for f in funcs}
    stale = sorted(set(ann) - names)
    if stale:
        raise GenError('gen_raw.py: ANNOTATIONS name functions the header lacks: %s' % ', '.join(stale))
    stale = sorted(set(FIELD_INIT) - {s[0] for s in structs})
    if stale:
        raise GenError('gen_raw.py: FIELD_INIT names structs the header lacks: %s' % ', '.join(stale))
    return {OUT_RAW: gen_raw(consts, structs, opaque, funptrs, funcs, ann),
            OUT_ABI: gen_abi(consts, structs),
            OUT_T901: gen_t901(consts, structs),
            OUT_MANIFEST: (consts, structs, opaque, funptrs, funcs)}, funcs


def unwrapped(funcs):
    """Public functions whose raw interface no wrapper of granary.f90 calls."""
    try:
        with open(os.path.join(ROOT, 'bindings/granary.f90')) as f:
            body = f.read().lower()
    except OSError:
        return []
    return [n for n, _, _ in funcs if n not in NOT_WRAPPED and re.search(r'\bc_%s\s*\(' % n, body.split('\ncontains\n', 1)[-1]) is None]


def main(argv):
    check = '--check' in argv[1:]
    release = '--release' in argv[1:]
    try:
        files, funcs = generate()
    except GenError as e:
        print('gen_raw.py: ' + str(e), file=sys.stderr)
        return 2
    # the manifest: its status carried over while the ABI number stays; a released ABI may only grow
    try:
        with open(os.path.join(ROOT, OUT_MANIFEST)) as f:
            old_manifest = f.read()
    except OSError:
        old_manifest = None
    abi = dict(files[OUT_MANIFEST][0])['GRAN_ABI_VERSION']
    try:
        n_old, st_old, l_old = manifest_parts(old_manifest) if old_manifest is not None else (None, None, [])
    except GenError as e:
        print('gen_raw.py: ' + str(e), file=sys.stderr)
        return 2
    if n_old is not None and abi < n_old:
        print('gen_raw.py: GRAN_ABI_VERSION %d in %s is lower than the %d of %s' % (abi, HEADER, n_old, OUT_MANIFEST),
              file=sys.stderr)
        return 1
    status = st_old if abi == n_old else 'unreleased'
    if release:
        status = 'released'
    files[OUT_MANIFEST] = gen_manifest(*files[OUT_MANIFEST], status)
    if abi == n_old and st_old == 'released':
        have = set(manifest_parts(files[OUT_MANIFEST])[2])
        gone = [x for x in l_old if x not in have]
        if gone:
            print('gen_raw.py: the public ABI %d is released and changed: these lines of %s are gone or'
                  ' changed:\n  %s\n  a program built against the released header would break: raise'
                  ' GRAN_ABI_VERSION in %s (see docs/developers/abi.md), or restore them; nothing was written'
                  % (abi, OUT_MANIFEST, '\n  '.join(gone[:20]) + ('\n  ...' if len(gone) > 20 else ''), HEADER),
                  file=sys.stderr)
            return 1
    bad = []
    for rel, content in files.items():
        path = os.path.join(ROOT, rel)
        try:
            with open(path) as f:
                old = f.read()
        except OSError:
            old = None
        if old == content:
            continue
        if check:
            bad.append(rel)
        else:
            with open(path, 'w') as f:
                f.write(content)
            print('gen_raw.py: wrote ' + rel)
    if bad:
        print('gen_raw.py: not current with %s: %s\n  regenerate with: %s' % (HEADER, ', '.join(bad), REGEN),
              file=sys.stderr)
        return 1
    missing = unwrapped(funcs)
    if missing:
        print('gen_raw.py: note: no wrapper in bindings/granary.f90 calls c_' + ', c_'.join(missing),
              file=sys.stderr)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
