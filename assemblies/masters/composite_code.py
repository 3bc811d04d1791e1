"""The composite FMU's model functions as loops over the members of each kind.

Flattened into one SX expression, a joined assembly generates C whose functions grow
with the whole assembly (a 32-block chain: 108,000 lines, one ``mf_out`` of 30,000, with
thousands of locals), and gcc's time on such functions grows faster than their length
(n = 16: 7 s, n = 32: 24 s, n = 64: over ten minutes). One call per member instead of
one expression changes nothing: CasADi writes every call out, and the functions stay
as long. (Small assemblies keep the flattened expression: FLAT_LIMIT.)

So each member's equations become small SX functions (its derivatives, each output,
its indicators, its jumps), one per *kind*: members whose equations are the same up to
parameter values (a chain's blocks) share them. The composite's functions are MX
graphs in which each kind's function is ``map``-ped over its members (a loop in the C),
its arguments gathered from one vector of values by index tables (data, not code):

    V = [0, t, x, q, u, p, outputs of level 1, outputs of level 2, ...]

An output of level L depends, through the inputs it uses, only on outputs of lower
levels (level 0: states, modes, parameters, open inputs); the connections are resolved
as :func:`.monolithic.join` resolves them (a connected input is ``gain *`` its source),
and each function takes only the inputs it uses, so that one member's acceleration
output feeding another's unused input is no loop. A member's outputs of one level are
one function, and its derivatives join the outputs of its highest level where the
inputs they use are known (one call per kind and level: a call's setup, not its few
flops, is what a member costs). The code then grows with the number of kinds and
levels, the tables with the members. CasADi's AD of the maps gives ``jac`` and ``dd``.

CasADi's C of the maps copies each argument of each map into a block of its own and
each result out again; ``ode``, ``out``, ``zc`` and ``jump``, evaluated at every step,
are instead written by :class:`MemberC` as loops that hand each member's function
pointers to its own states, modes and parameters and gather only its inputs. The
flattened SX model stays the reference: the same values, compared in
tests/unit/test_composite_code.py (the MX functions directly, MemberC's compiled).
"""
from __future__ import annotations

import bisect
from collections import defaultdict

from components.lazy import lazy

ca = lazy("casadi")


class _Kinds:
    """One SX function per distinct member equation: members that differ only in their
    parameter values share it."""

    def __init__(self):
        self.by_key: dict[str, ca.Function] = {}

    def function(self, what: str, member, outputs: list, used=None) -> ca.Function:
        """`outputs` of the member's (t, x, q, u, p); with `used`, of its inputs u[used]
        alone (an output's own: the others are not gathered for it)."""
        outputs = [ca.densify(o) for o in outputs]
        args = list(member.args)
        if used is not None:
            args[3] = ca.vertcat(ca.SX(0, 1), *[member.u[i] for i in used])
        key = what + ca.Function("kind", args, outputs).serialize()
        if key not in self.by_key:
            self.by_key[key] = ca.Function(f"mf_kind{len(self.by_key)}_{what}", args, outputs)
        return self.by_key[key]


class _Values:
    """The vector V of the module doc, kept as its parts: slots are handed out in order,
    and a gather reads each part it needs directly (concatenating V at every level
    would copy all of it each time: most of a small composite's run time)."""

    def __init__(self, head: list):
        self.parts, self.firsts, self.size = [], [], 0
        for block in head:
            self.add(block)

    def add(self, block: ca.MX) -> int:
        """Append the column-major entries of `block`; the slot of its first entry."""
        first = self.size
        self.parts.append(ca.vec(block))
        self.firsts.append(first)
        self.size += block.numel()
        return first

    def gather(self, rows: list[int]) -> ca.MX:
        """V[rows] as an MX column."""
        pieces: dict[int, list[tuple[int, int]]] = defaultdict(list)  # part -> (offset, position)
        for pos, r in enumerate(rows):
            k = bisect.bisect_right(self.firsts, r) - 1
            pieces[k].append((r - self.firsts[k], pos))
        order, blocks = [], []
        for k in sorted(pieces):
            offsets = [o for o, _ in pieces[k]]
            part = self.parts[k]
            blocks.append(part if offsets == list(range(part.numel())) else ca.vec(part[offsets]))
            order += [pos for _, pos in pieces[k]]
        v = ca.vertcat(*blocks)
        if order != list(range(len(rows))):
            inverse = [0] * len(order)
            for i, pos in enumerate(order):
                inverse[pos] = i
            v = ca.vec(v[inverse])
        return v


# Below this many SX instructions (derivatives, outputs, indicators, jumps) the flattened
# expression is kept: gcc builds it in seconds, and its straight-line C runs faster
# than the member loops on small assemblies (a chain of 16 blocks in the engine's
# monolithic mode: 8.9 against 13.4 us of engine per step; before MemberC the maps ran
# two_block_belt, 467, at 1.5 against 3.2 ms at tolerance 1e-5). The count is of the join's shared graph
# (monolithic.substitute_all: a resolved input is one node wherever it is read), but
# gcc's time follows the C that is written, which did not shrink with it: a chain of
# 16 blocks (3,594 instructions) builds in 7 s, 32 (7,194) took 30 s of gcc CPU and 88
# (19,794) over 2 minutes. So the limit sits where it was in C terms (it was 20,000
# when the same chains counted 17,266 and 35,042). Every scene of the library but
# coupled_clutches (24,812: its loop solved per mode combination) is below it.
FLAT_LIMIT = 4_100


def worth_mapping(model) -> bool:
    """Whether the flattened `model` is too large to compile as one expression."""
    from fmus.codegen import computed_outputs
    whole = ca.Function("size", model.args, [model.xdot, computed_outputs(model), model.z,
                                             model.jump_x, model.jump_q])
    return whole.n_instructions() > FLAT_LIMIT


def member_functions(joined, model, c_code: bool = False) -> dict:
    """The composite's ``ode``, ``out``, ``zc``, ``jump``, ``jac`` and ``dd`` (keys of
    fmus.codegen) as MX functions of the flattened composite `model`'s arguments, or {}
    when a variable of `model` has no member counterpart (then the flattened functions
    are used as they are). With `c_code`, also ``c``: a :class:`MemberC` that writes
    ``ode``, ``out``, ``zc`` and ``jump`` as C loops calling each kind's function on
    its members in place (fmus.codegen uses it instead of CasADi's C for those four)."""
    members = joined.members
    names = {key: [v.name for v in getattr(model, attr)] for key, attr in
             (("x", "states"), ("q", "modes"), ("u", "inputs"), ("p", "parameters"))}
    t = ca.MX.sym("t")
    args = {k: ca.MX.sym(k, len(names[k])) for k in ("x", "q", "u", "p")}
    # slot 0 is a zero: the value of an input an output does not depend on
    values = _Values([ca.MX(ca.DM.zeros(1)), t])
    slot: dict[tuple[str, str], int] = {}
    arg_first = {}
    for key in ("x", "q", "u", "p"):
        first = arg_first[key] = values.add(args[key])
        for i, full in enumerate(names[key]):
            inst, _, var = full.partition(".")
            slot[(inst, var)] = first + i
    for name, m in members.items():
        for v in (*m.states, *m.modes, *m.parameters):
            if (name, v.name) not in slot:
                return {}
    for inst, var in joined.open_inputs:
        if (inst, var) not in slot:
            return {}
    y_names = [v.name.partition(".")[::2] for v in model.outputs]
    if any(inst not in members for inst, _ in y_names) or \
            sum(m.z.numel() for m in members.values()) != model.z.numel():
        return {}

    feeds = {c.target: c for c in joined.couplings}
    kinds = _Kinds()

    # --- where each member input comes from: (level-resolved source, gain) ------------
    level: dict[tuple[str, str], int] = {}   # member output -> its level
    uses: dict[tuple[str, int], list[int]] = {}  # (member, output j) -> inputs it uses

    def used_inputs(name, j):
        if (name, j) not in uses:
            m = members[name]
            uses[(name, j)] = [i for i in range(m.u.numel()) if ca.depends_on(m.y[j], m.u[i])]
        return uses[(name, j)]

    def source(name, var):
        """(instance, variable, gain) a member input reads, through inputs fed by inputs."""
        gain = 1.0
        while (name, var) not in joined.open_inputs and (name, var) in feeds:
            c = feeds[(name, var)]
            gain *= c.gain
            name, var = c.source
            if var not in [v.name for v in members[name].inputs]:
                break
        return name, var, gain

    def level_of(name, var):
        outputs = [v.name for v in members[name].outputs]
        if var not in outputs or (name, var) in slot:
            return 0
        if (name, var) not in level:
            j = outputs.index(var)
            inputs = members[name].inputs
            level[(name, var)] = 1 + max(
                (level_of(*source(name, inputs[i].name)[:2]) for i in used_inputs(name, j)),
                default=0)
        return level[(name, var)]

    wanted = {(inst, var) for inst, var in y_names}
    for name, m in members.items():  # every input of every member is read by ode/zc/jump
        for v in m.inputs:
            if (name, v.name) not in slot and v.rate_of is None:
                wanted.add(source(name, v.name)[:2])
    # the outputs of a member of the same level are one function (they share the work,
    # a friction block's acceleration, support force and friction power, and each call
    # costs its arguments' setup: a block's positions and velocities, two functions when
    # grouped by the inputs they use, are one), of the inputs any of them uses, evaluated
    # for every member once any of them is wanted
    group_of: dict[tuple[str, int], tuple] = {}
    for inst in {inst for inst, _ in wanted}:
        m = members[inst]
        same: dict[int, list[int]] = defaultdict(list)
        for j, v in enumerate(m.outputs):
            same[level_of(inst, v.name)].append(j)
        for js in same.values():
            used = tuple(sorted({i for j in js for i in used_inputs(inst, j)}))
            for j in js:
                group_of[(inst, j)] = (tuple(js), used)
    def inputs_of(expr, m) -> tuple:
        return tuple(i for i in range(m.u.numel()) if ca.depends_on(expr, m.u[i]))

    # a member's derivatives join its outputs of the highest level where every input
    # they use is known by then (a friction block's accelerations and its derivatives
    # share the mode logic; a source's travel needs no input): one call less per member
    fused: dict[str, int] = {}
    for inst, var in wanted:
        if (inst, var) not in slot:
            fused[inst] = max(fused.get(inst, 0), level_of(inst, var))
    for inst, top in list(fused.items()):
        m = members[inst]
        if not m.x.numel() or any(level_of(*source(inst, m.inputs[i].name)[:2]) >= top
                                  for i in inputs_of(m.xdot, m)):
            del fused[inst]
    by_level: dict[int, dict] = defaultdict(lambda: defaultdict(list))
    # in the members' order, not the set's (hashed strings: a new order in each process):
    # a map's gathers then read its members' slots in runs and strides instead of a
    # scattered index table per argument, and the same assembly writes the same C
    rank = {name: k for k, name in enumerate(members)}
    for inst, var in sorted(wanted, key=lambda w: (rank[w[0]], w[1])):
        if (inst, var) not in slot:
            outputs = [v.name for v in members[inst].outputs]
            if var not in outputs:
                return {}
            js, used = group_of[(inst, outputs.index(var))]
            m, lvl = members[inst], level_of(inst, var)
            what, result = "y" + "_".join(map(str, js)), [m.y[j] for j in js]
            if fused.get(inst) == lvl:
                what, result = what + "_ode", result + [m.xdot]
                used = tuple(sorted({*used, *inputs_of(m.xdot, m)}))
            fn = kinds.function(what, m, [ca.vertcat(*result)], used)
            if inst not in by_level[lvl][(fn, js, used)]:
                by_level[lvl][(fn, js, used)].append(inst)

    def gather(rows: list[int], gains: list[float], shape) -> ca.MX:
        if not rows:
            return ca.MX(*shape)
        v = values.gather(rows)
        if any(g != 1.0 for g in gains):
            v = v * ca.DM(gains)
        return ca.reshape(v, *shape)

    calls: list[_Call] = []

    def call(fn, insts, u_rows) -> ca.MX:
        """`fn` mapped over `insts`, the inputs from `u_rows(inst)` -> [(slot, gain)];
        recorded (calls[-1]) for the C that calls `fn` member by member."""
        k = len(insts)
        x, q, p, u, gains = [], [], [], [], []
        for inst in insts:
            m = members[inst]
            x += [slot[(inst, v.name)] for v in m.states]
            q += [slot[(inst, v.name)] for v in m.modes]
            p += [slot[(inst, v.name)] for v in m.parameters]
            for s, g in u_rows(inst):
                u.append(s)
                gains.append(g)
        calls.append(_Call(fn, k, x, q, u, gains, p))
        m = members[insts[0]]
        ins = [t, gather(x, [1.0] * len(x), (m.x.numel(), k)),
               gather(q, [1.0] * len(q), (m.q.numel(), k)),
               gather(u, gains, (fn.numel_in(3), k)), gather(p, [1.0] * len(p), (m.p.numel(), k))]
        return fn.map(k)(*ins)

    def input_rows(inst, used=None):
        rows = []
        for i, v in enumerate(members[inst].inputs):
            if used is not None and i not in used:  # not an argument of the function
                continue
            if (inst, v.name) in slot:  # open: the composite's own input
                rows.append((slot[(inst, v.name)], 1.0))
                continue
            if v.rate_of is not None:  # read by a co-simulation step only: 0 (monolithic)
                rows.append((0, 1.0))
                continue
            src, var, gain = source(inst, v.name)
            rows.append((slot[(src, var)], gain))
        return rows

    xdot_at: dict[str, int] = {}
    for lvl in sorted(by_level):
        for (fn, js, used), insts in by_level[lvl].items():
            first = values.add(call(fn, insts, lambda inst, used=used: input_rows(inst, used)))
            calls[-1].firsts = [first]
            rows = fn.numel_out(0)  # the outputs js, then the derivatives where fused
            for c, inst in enumerate(insts):
                for r, j in enumerate(js):
                    slot[(inst, members[inst].outputs[j].name)] = first + c * rows + r
                if rows > len(js):
                    for i, v in enumerate(members[inst].states):
                        xdot_at[f"{inst}.{v.name}"] = first + c * rows + len(js) + i

    # --- derivatives, indicators, jumps: every kind mapped over its members ------------
    # (each function of the inputs it uses: the others are not gathered for it)
    groups: dict[tuple, list[str]] = defaultdict(list)
    for name, m in members.items():
        ode_u, zc_u = inputs_of(m.xdot, m), inputs_of(m.z, m)
        jump_u = inputs_of(ca.vertcat(m.jump_x, m.jump_q), m)
        groups[(kinds.function("ode", m, [m.xdot], ode_u) if m.x.numel() and name not in fused
                else None, ode_u,
                kinds.function("zc", m, [m.z], zc_u) if m.z.numel() else None, zc_u,
                kinds.function("jump", m, [m.jump_x, m.jump_q], jump_u)
                if m.x.numel() or m.q.numel() else None, jump_u)].append(name)
    z_at, x_new_at, q_new_at = {}, {}, {}
    for (ode, ode_u, zc, zc_u, jump, jump_u), insts in groups.items():
        def rows(used):
            return lambda inst: input_rows(inst, used)
        if ode is not None:
            first = values.add(call(ode, insts, rows(ode_u)))
            calls[-1].firsts = [first]
            _place(xdot_at, first, insts, lambda i: members[i].states, slot, "x")
        if zc is not None:
            first = values.add(call(zc, insts, rows(zc_u)))
            calls[-1].firsts = [first]
            for c, inst in enumerate(insts):
                n = members[inst].z.numel()
                z_at[inst] = list(range(first + c * n, first + (c + 1) * n))
        if jump is not None:
            jx, jq = call(jump, insts, rows(jump_u))
            calls[-1].firsts = [None, None]  # an empty result has no slots
            if jx.numel():
                calls[-1].firsts[0] = values.add(jx)
                _place(x_new_at, calls[-1].firsts[0], insts, lambda i: members[i].states, slot, "x")
            if jq.numel():
                calls[-1].firsts[1] = values.add(jq)
                _place(q_new_at, calls[-1].firsts[1], insts, lambda i: members[i].modes, slot, "q")
    x_index = {full: i for i, full in enumerate(names["x"])}
    q_index = {full: i for i, full in enumerate(names["q"])}

    def pick(rows):
        return ca.densify(values.gather(rows)) if rows else ca.MX(0, 1)

    xdot_rows = [xdot_at[full] for full in sorted(xdot_at, key=x_index.__getitem__)]
    x_new_rows = [x_new_at.get(full, slot[tuple(full.split(".", 1))]) for full in names["x"]]
    q_new_rows = [q_new_at.get(full, slot[tuple(full.split(".", 1))]) for full in names["q"]]
    if len(xdot_rows) != len(names["x"]) or len(q_index) != len(q_new_rows):
        return {}
    XDOT = pick(xdot_rows)
    Y = pick([slot[key] for key in y_names])
    z_rows = [r for name in members for r in z_at.get(name, [])]
    Z = pick(z_rows)
    ins, arg_names = [t, args["x"], args["q"], args["u"], args["p"]], ["t", "x", "q", "u", "p"]
    unknowns, knowns = ca.vertcat(XDOT, Y, Z), ca.vertcat(args["x"], args["u"])
    dd = ca.jacobian(unknowns, knowns) if knowns.numel() else ca.MX(unknowns.numel(), 0)
    functions = {
        "ode": ca.Function("mf_ode", ins, [XDOT], arg_names, ["xdot"]),
        "out": ca.Function("mf_out", ins, [ca.densify(ca.vertcat(Y, Z))], arg_names, ["y"]),
        "zc": ca.Function("mf_zc", ins, [Z], arg_names, ["z"]),
        "jump": ca.Function("mf_jump", ins, [pick(x_new_rows), pick(q_new_rows)], arg_names,
                            ["x_new", "q_new"]),
        "jac": ca.Function("mf_jac", ins, [ca.densify(ca.jacobian(XDOT, args["x"]))], arg_names,
                           ["jac"]),
        "dd": ca.Function("mf_dd", ins, [dd], arg_names, ["dd"]),
    }
    if c_code:
        sizes = {key: args[key].numel() for key in ("x", "q", "u", "p")}
        functions["c"] = MemberC(calls, values.size, arg_first, sizes, {
            "ode": [xdot_rows], "zc": [z_rows], "out": [[slot[key] for key in y_names] + z_rows],
            "jump": [x_new_rows, q_new_rows]})
    return functions


def _place(where: dict, first: int, insts: list[str], variables, slot, key) -> None:
    """Record the slot of each member variable's result in a mapped block (column-major:
    member c's rows follow c * rows)."""
    for c, inst in enumerate(insts):
        vs = variables(inst)
        for i, v in enumerate(vs):
            where[f"{inst}.{v.name}"] = first + c * len(vs) + i


class _Call:
    """One kind's function mapped over k members: the slots of V each member's x, q, u
    (with gains) and p are read from, member after member, and the first slot of each
    result block (member c's rows of result j follow at firsts[j] + c * rows_j)."""

    def __init__(self, fn, k, x, q, u, gains, p):
        self.fn, self.k, self.x, self.q, self.u, self.gains, self.p = fn, k, x, q, u, gains, p
        self.firsts: list[int | None] = []

    def reads(self) -> set[int]:
        return {1, *self.x, *self.q, *self.u, *self.p}

    def writes(self) -> list[tuple[int, int]]:
        """[(first, count)] of the slots its results fill."""
        return [(f, self.k * self.fn.numel_out(j)) for j, f in enumerate(self.firsts)
                if f is not None]


def _c_table(name: str, values: list) -> str:
    body = ", ".join(map(str, values))
    return f"static const casadi_int {name}[{len(values)}] = {{{body}}};"


class MemberC:
    """C for the composite's ``ode``, ``out``, ``zc`` and ``jump``, calling each kind's
    function member by member with pointers into one work vector V (the module doc's):
    a member's states, modes and parameters are its own consecutive slots, so only its
    inputs (connected outputs times their gains) are gathered, and each call writes its
    results where V keeps them. CasADi's C of the maps copies every argument of every map
    into a block of its own, and every result out of it again: per block and right-hand
    side about 75 values moved around 15 flops of the members' own equations (perf, a
    256-block chain: 57 % of the run in those copies). ``jac`` and ``dd`` stay CasADi's
    (the AD of the maps, evaluated rarely)."""

    FUNCTIONS = ("ode", "out", "zc", "jump")

    def __init__(self, calls: list[_Call], v_size: int, arg_first: dict, sizes: dict,
                 results: dict):
        self.calls, self.v_size, self.arg_first, self.sizes = calls, v_size, arg_first, sizes
        self.results = results
        for c in calls:
            assert len(c.firsts) == c.fn.n_out(), "a mapped call without its result slots"
            assert all(0 <= r < v_size for r in c.reads())
            assert all(0 <= f and f + n <= v_size for f, n in c.writes())
        assert all(0 <= r < v_size for rows in (x for v in results.values() for x in v)
                   for r in rows)

    @property
    def kernels(self) -> list:
        """Each kind's function once, for the code generator to write (as mf_kind*)."""
        seen = {}
        for c in self.calls:
            seen.setdefault(c.fn.name(), c.fn)
        return list(seen.values())

    def _needed(self, rows) -> list[int]:
        """Indices of the calls the slots `rows` depend on, in the calls' order."""
        producer = {}
        for i, c in enumerate(self.calls):
            for first, n in c.writes():
                for r in range(first, first + n):
                    producer[r] = i
        needed, todo = set(), [producer[r] for r in rows if r in producer]
        while todo:
            i = todo.pop()
            if i not in needed:
                needed.add(i)
                todo += [producer[r] for r in self.calls[i].reads() if r in producer]
        return sorted(needed)

    def _call_c(self, i: int, c: _Call) -> tuple[list[str], int]:
        """The C of call `i` as a function of V, and the scratch values it needs."""
        fn, k = c.fn, c.k
        lines, body, scratch = [], [], 0
        for a, (rows, key) in enumerate(((c.x, "x"), (c.q, "q"), (c.u, "u"), (c.p, "p")), 1):
            n = len(rows) // k if k else 0
            if n == 0:
                body.append(f"        a[{a}] = 0;")
                continue
            per = [rows[m * n:(m + 1) * n] for m in range(k)]
            gains = c.gains if key == "u" and any(g != 1.0 for g in c.gains) else None
            if gains is None and all(r == list(range(r[0], r[0] + n)) for r in per):
                first, size = self.arg_first.get(key), self.sizes.get(key, 0)
                if all(first is not None and first <= r[0] and r[-1] < first + size for r in per):
                    # the member's own states, modes or parameters: read where they are
                    lines.append(_c_table(f"mfc{i}_{key}", [r[0] - first for r in per]))
                    body.append(f"        a[{a}] = in[{a}] + mfc{i}_{key}[c];")
                else:
                    lines.append(_c_table(f"mfc{i}_{key}", [r[0] for r in per]))
                    body.append(f"        a[{a}] = V + mfc{i}_{key}[c];")
                    self._in_v.update(x for r in per for x in r)
                continue
            self._in_v.update(rows)
            lines.append(_c_table(f"mfc{i}_{key}", rows))
            read = f"V[mfc{i}_{key}[c * {n} + j]]"
            if gains is not None:
                lines.append(f"static const casadi_real mfc{i}_{key}_gain[{len(gains)}] = "
                             f"{{{', '.join(repr(float(g)) for g in gains)}}};")
                read = f"mfc{i}_{key}_gain[c * {n} + j] * {read}"
            body.append(f"        for (j = 0; j < {n}; ++j) s[{scratch} + j] = {read};")
            body.append(f"        a[{a}] = s + {scratch};")
            scratch += n
        for j, first in enumerate(c.firsts):
            rows = fn.numel_out(j)
            body.append(f"        r[{j}] = V + {first} + c * {rows};" if first is not None
                        else f"        r[{j}] = 0;")
        lines += [f"/* {fn.name()} on each of {k} members */",
                  f"static int mfc_call{i}(casadi_real *V, const casadi_real *const *in, "
                  "casadi_int *iw, casadi_real *s, casadi_real *kw) {",
                  "    casadi_int c, j;",
                  f"    const casadi_real *a[{self._ka}] = {{0}};",
                  f"    casadi_real *r[{self._kr}] = {{0}};",
                  "    (void)j; (void)s;",
                  "    a[0] = V + 1;",
                  f"    for (c = 0; c < {k}; ++c) {{", *body,
                  f"        if ({fn.name()}(a, r, iw, kw, 0)) return 1;",
                  "    }", "    return 0;", "}"]
        return lines, scratch

    def text(self) -> str:
        """The C, to follow CasADi's (it calls the mf_kind* functions written there)."""
        kernels = self.kernels
        self._in_v = set()  # the slots of x, q, u, p read from V (the rest: from the arguments)
        self._ka = max([5] + [f.sz_arg() for f in kernels])
        self._kr = max([2] + [f.sz_res() for f in kernels])
        iw = max([0] + [f.sz_iw() for f in kernels])
        kw = max([0] + [f.sz_w() for f in kernels])
        calls, scratch = [], 1
        for i, c in enumerate(self.calls):
            lines, s = self._call_c(i, c)
            calls += lines
            scratch = max(scratch, s)
        self._in_v.update(r for rows in self.results.values() for x in rows for r in x)
        # an argument's values are copied into V where V is read at their slots (a
        # member's input that is another's state, a result that is a state); an absent
        # argument (NULL: zeros) is cleared there and read there
        out = ["/* the composite's ode, out, zc and jump: assemblies/masters/composite_code.py "
               "MemberC */",
               "static void mfc_load(const casadi_real **arg, casadi_real *V, "
               "const casadi_real **in) {",
               "    casadi_int i;", "    (void)i;",
               "    V[0] = 0;", "    V[1] = arg[0] ? arg[0][0] : 0;", "    in[0] = V + 1;"]
        for a, key in enumerate(("x", "q", "u", "p"), 1):
            n, first = self.sizes[key], self.arg_first[key]
            if not n:
                out.append(f"    in[{a}] = 0;")
                continue
            copy = any(first <= r < first + n for r in self._in_v)
            out += [f"    if (arg[{a}]) {{", f"        in[{a}] = arg[{a}];",
                    *([f"        for (i = 0; i < {n}; ++i) V[{first} + i] = arg[{a}][i];"]
                      if copy else []),
                    "    } else {", f"        for (i = 0; i < {n}; ++i) V[{first} + i] = 0;",
                    f"        in[{a}] = V + {first};", "    }"]
        out.append("}")
        out += calls
        w = self.v_size + scratch + kw
        for name in self.FUNCTIONS:
            results = self.results[name]
            needed = self._needed([r for rows in results for r in rows])
            for j, rows in enumerate(results):
                if rows:
                    out.append(_c_table(f"mfc_{name}_r{j}", rows))
            out += [f"int mf_{name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, "
                    "casadi_real* w, int mem) {",
                    f"    casadi_real *V = w, *s = w + {self.v_size}, "
                    f"*kw = w + {self.v_size + scratch};",
                    "    const casadi_real *in[5];",
                    "    casadi_int i;", "    (void)i; (void)mem; (void)s; (void)kw;",
                    "    mfc_load(arg, V, in);"]
            out += [f"    if (mfc_call{i}(V, in, iw, s, kw)) return 1;" for i in needed]
            for j, rows in enumerate(results):
                if rows:
                    out.append(f"    if (res[{j}]) for (i = 0; i < {len(rows)}; ++i) "
                               f"res[{j}][i] = V[mfc_{name}_r{j}[i]];")
            out += ["    return 0;", "}",
                    f"int mf_{name}_work(casadi_int *sz_arg, casadi_int* sz_res, "
                    "casadi_int *sz_iw, casadi_int *sz_w) {",
                    f"    if (sz_arg) *sz_arg = 5;", f"    if (sz_res) *sz_res = {max(1, len(results))};",
                    f"    if (sz_iw) *sz_iw = {iw};", f"    if (sz_w) *sz_w = {w};",
                    "    return 0;", "}"]
        return "\n".join(out) + "\n"
