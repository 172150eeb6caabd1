"""Every table and key of a scene, assembled from the fixed tables, the models and the effects.

:func:`schema` returns ``{table: {key: Key}}`` (``""`` the top level, ``damper.load`` a sub-table of
``damper``).  The ``[damper]`` table holds the bar's keys plus every registered model's own keys
(``hbm.scenes.models``, which also holds the keys every model shares, ``BASE_DAMPER_KEYS``); the
``[effects]`` table the keys of the registered effects
(``hbm.scenes.effects``) plus ``tolerance``.  ``python3 -m hbm keys`` prints it.
"""

from __future__ import annotations

from typing import Iterator

from .._validation import MIN_RELATIVE_TOL
from ..balance import presets
from ..frf import DEFAULT_TOL
from .checks import (Invalid, Key, OPTIONAL, REQUIRED, dot, formats, integer, nonnegative, number, number_list,
                     number_or_name, one_or_list, positive, text, choice, inner_folder, boolean)
from .contacts import contact_tables, dof_pair_list
from .effects import EFFECTS, samples_key
from .models import BASE_DAMPER_KEYS, MODELS
from .sampling import study_keys

def any_integer(v):
    """An integer of any sign (booleans refused); raises :class:`Invalid`."""
    if isinstance(v, bool) or not isinstance(v, int):
        raise Invalid("must be an integer")
    return int(v)


#: Sweep units of ``sweep.omega``: name -> factor to rad/s (``omega_c`` is the bar's, set per scene).
OMEGA_UNITS = ("rad/s", "Hz", "omega_c")

_FIXED: dict[str, dict[str, Key]] = {
    "": {
        "title": Key(text, "", "a one-line description, copied to the summary"),
    },
    "blade": {
        "mass": Key(number(gt=0, unit="kg"), REQUIRED, "modal mass m (kg)"),
        "stiffness": Key(number(ge=0, unit="N/m"), OPTIONAL, "stiffness k (N/m); give this or `frequency`"),
        "frequency": Key(number(gt=0, unit="rad/s"), OPTIONAL,
                         "natural frequency of the blade alone, sqrt(k/m) (rad/s); give this or `stiffness`"),
        "damping": Key(number(ge=0, unit="N s/m"), OPTIONAL,
                       "viscous damping c (N s/m); give this or `damping_ratio`"),
        "damping_ratio": Key(number(ge=0), OPTIONAL,
                             "viscous damping ratio zeta, c = 2 zeta sqrt(k m); give this or `damping`"),
        "force": Key(number(gt=0, unit="N"), REQUIRED, "force amplitude F of F cos(omega t) (N)"),
    },
    "structure": {
        "mass": Key(text, REQUIRED, "mass matrix M: a file (.mtx Matrix Market, .npz, .npy; \"file.npz:key\" picks "
                                    "an array of an .npz), relative to the scene file"),
        "stiffness": Key(text, REQUIRED, "stiffness matrix K: a file, as structure.mass"),
        "damping": Key(text, OPTIONAL, "damping matrix C: a file; or give structure.rayleigh or "
                                       "structure.modal_damping (exactly one of the three)"),
        "rayleigh": Key(number_list(nonnegative, length=2), OPTIONAL, "[alpha, beta]: C = alpha M + beta K"),
        "modal_damping": Key(one_or_list(nonnegative, "a number >= 0"), OPTIONAL,
                             "modal damping ratio zeta of every mode, or a list with one per mode"),
        "force": Key(number_list(number(unit="N")), REQUIRED,
                     "force amplitudes of F cos(omega t), one per DOF (N)"),
        "contact_dofs": Key(dof_pair_list, REQUIRED,
                            "where the damper acts: [i] (DOF i to ground) or [i, j] (on x_i - x_j); the tangential "
                            "displacement of a two-component damper (contact2d, allmode2d), the first of a "
                            "three-component one (contact3d)"),
        "second_dofs": Key(dof_pair_list, OPTIONAL,
                           "three-component damper (contact3d) only, required for it: its second tangential "
                           "displacement, [k] (DOF k to ground) or [k, l] (x_k - x_l)"),
        "normal_dofs": Key(dof_pair_list, OPTIONAL,
                           "two- or three-component damper (contact2d, allmode2d, contact3d) only, required for it: "
                           "its normal displacement, [k] (DOF k to ground) or [k, l] (x_k - x_l, v > 0 pressing)"),
        "contacts": Key(contact_tables, OPTIONAL,
                        "further elements of the structure, the same in every run: [[structure.contacts]] tables, "
                        "each with model (a registered model complete in its own keys), dofs ([i] or [i, j]), "
                        "normal_dofs (contact2d, contact3d), second_dofs (contact3d) and the model's keys as in "
                        "[damper]"),
        "response_dof": Key(integer(0), OPTIONAL, "the DOF whose response is reported; default the forced DOF"),
        "sectors": Key(integer(2), OPTIONAL,
                       "N: the matrices are one sector of a tuned cyclic structure (a bladed disk) of N sectors "
                       "(at most hbm.cyclic.MAX_SECTORS), "
                       "solved as hbm.CyclicStructure; requires structure.engine_order"),
        "engine_order": Key(any_integer, OPTIONAL,
                            "with structure.sectors, required: EO, the engine order of the travelling-wave force "
                            "(sector j's lags sector 0's by 2 pi EO j / N; reduced mod N, negative: backward)"),
        "next_stiffness": Key(text, OPTIONAL,
                              "with structure.sectors: the coupling K_next of this sector's DOFs (rows) to the next "
                              "sector's (columns), a file as structure.mass; default zero"),
        "next_mass": Key(text, OPTIONAL, "with structure.sectors: the coupling M_next, a file; default zero"),
        "next_damping": Key(text, OPTIONAL,
                            "with structure.sectors and structure.damping: the coupling C_next, a file; default "
                            "zero (with structure.rayleigh C_next = alpha M_next + beta K_next)"),
        "next_sector": Key(boolean, False,
                           "with structure.sectors: true puts the damper between the next sector and this one, "
                           "structure.contact_dofs = [p, q] acting on x_p of the next sector minus x_q of this one"),
    },
    "damper.load": {
        "kind": Key(choice("uniform", "quadratic", "centrifugal"), "uniform",
                    '"uniform" (q = N/L), "quadratic" (Eq. 29: q0 + q2 4x(x - L)/L^2) or "centrifugal" (uniform, '
                    'N = mass radius (omega/engine_order)^2 at each drive frequency)'),
        "N": Key(one_or_list(number(ge=0, unit="N"), "a number >= 0 (N)"), OPTIONAL,
                 "total normal load (N), or a list of loads (one run each: a design chart)"),
        "ratio": Key(number(gt=0, allow_inf=True), OPTIONAL,
                     "quadratic only: q0/(q0 - q2); > 1 concave (three regions), < 1 convex"),
        "q0": Key(nonnegative, OPTIONAL, "quadratic only, instead of N and ratio: q0 (N/m)"),
        "q2": Key(number(unit="N/m"), OPTIONAL, "quadratic only, instead of N and ratio: q2 (N/m)"),
        "mass": Key(number(gt=0, unit="kg"), OPTIONAL, "centrifugal only, required: the damper's mass (kg)"),
        "radius": Key(number(gt=0, unit="m"), OPTIONAL, "centrifugal only, required: the damper's radius (m)"),
        "engine_order": Key(integer(1), OPTIONAL,
                            "centrifugal only, required: EO, the drive omega = EO times the rotation speed"),
    },
    "sweep": {
        "kind": Key(choice("frequency", "amplitude"), "frequency",
                    '"frequency" (an FRF of the blade) or "amplitude" (a table of F_s, F_c of the damper); '
                    'left out with [modes] or [optimum], which compute a nonlinear mode or the damper optimum'),
        "omega": Key(lambda v: v, REQUIRED,
                     "frequency: [w0, w1], the range traced from w0 to w1; amplitude: the list of "
                     "frequencies of the table"),
        "unit": Key(choice(*OMEGA_UNITS), "rad/s",
                    '"rad/s", "Hz", or "omega_c" (fractions of the bar\'s omega_c) for sweep.omega'),
        "tolerance": Key(number(ge=MIN_RELATIVE_TOL, lt=presets.MAX_RTOL), OPTIONAL,
                         f"deprecated (it warns): the elements' relative accuracy (rtol), which sweep.tol "
                         f"now sets (tol/100, at most {presets.DEFAULT_RTOL:g}); give sweep.tol"),
        "tol": Key(number_or_name(number(ge=MIN_RELATIVE_TOL, lt=1), presets.TOLERANCE), OPTIONAL,
                   "target relative error of the response amplitude against the physical system "
                   "(frequency_response's tol): the error estimate's target, the warning's threshold, the target "
                   'of the peak\'s refinement and what damper.model = "auto" holds the single-mode bar to; a number '
                   "or a name (" + ", ".join(f'"{n}" {t:g}' for n, t in presets.TOLERANCE.items()) +
                   f", as frequency_response's tol); default {DEFAULT_TOL:g}; not sweep.tolerance, the elements' rtol"),
        "accuracy": Key(choice(*presets.NAMED), OPTIONAL,
                        "deprecated (it warns): a preset of an earlier release, the tolerance of its name with that "
                        "release's element rtol and steps (" +
                        ", ".join(f'"{n}" rtol {r:g}' for n, r in presets.NAMED.items()) +
                        "); give sweep.tol, which takes the same names"),
        "max_step": Key(positive, OPTIONAL,
                        f"largest continuation step (scaled arclength); default {presets.DEFAULT_MAX_STEP:g}"),
        "min_step": Key(positive, OPTIONAL, f"smallest continuation step; default {presets.DEFAULT_MIN_STEP:g}"),
        "max_steps": Key(integer(1), OPTIONAL, f"step budget of the continuation; default {presets.DEFAULT_MAX_STEPS}"),
        "amplitude": Key(number_list(positive, length=2), OPTIONAL,
                         "amplitude sweep: [a0, a1], log-spaced (in sweep.amplitude_unit)"),
        "amplitude_unit": Key(choice("model", "a_min", "m"), "model",
                              'amplitude sweep: "model" (the model\'s unit: a_min = mu N/(k L) for the bar, '
                              'the paper\'s normalisation), "a_min" (the same, refused for a model without a '
                              'slip amplitude) or "m"'),
        "points": Key(integer(2), 50, "amplitude sweep: amplitudes per frequency"),
    },
    "modes": {
        "mode": Key(integer(0), 0, "which mode: the linear mode of the stuck system (0 the lowest) the branch starts from"),
        "amplitude": Key(number_list(positive, length=2), OPTIONAL,
                         "[a0, a1], a0 < a1: the modal amplitudes a traced (a^2 = sum_h Q_h^H M Q_h; for a blade "
                         "a = sqrt(m) x); give this or modes.amplitudes"),
        "amplitudes": Key(number_list(positive), OPTIONAL,
                          "the mode at exactly these modal amplitudes (within modes.amplitude when both are given)"),
    },
    "optimum": {
        "parameter": Key(text, REQUIRED,
                         'the damper key varied: "damper.load.N" (the normal load) or any number of [damper] or '
                         '[damper.load] the scene gives, e.g. "damper.mu"'),
        "bounds": Key(number_list(number(), length=2), REQUIRED,
                      "[p0, p1], p0 < p1: the parameter's range; the resonance peak is followed from p0 "
                      "(modes.amplitude must hold the peak at p0)"),
    },
    "output": {
        "folder": Key(inner_folder, OPTIONAL, "output folder, relative to the scene file's folder and inside it "
                      "(--out writes elsewhere); default the scene file's name without .toml"),
        "formats": Key(formats, ("csv", "png", "json"), 'which outputs: any of "csv", "png", "json"'),
    },
}

#: Sub-tables (parent table -> child key).
SUBTABLES = {"damper": "load"}
#: Tables a scene must have, and what they hold at least.
REQUIRED_TABLES = {"damper": "the damper: model, bar parameters, [damper.load]",
                   "sweep": "at least sweep.omega"}


def _model_names(v):
    return choice(*MODELS)(v)


def schema() -> dict[str, dict[str, Key]]:
    """Every table and key of a scene as registered now: ``{table: {key: Key}}``.

    Returns
    -------
    dict
        Table name -> {key name -> ``Key``}: ``""`` the top level, then ``blade``,
        ``structure``, ``damper`` (the bar's keys and every registered model's own keys),
        ``damper.load``, ``effects`` (every registered effect's key and ``tolerance``),
        ``sweep``, ``modes`` and ``optimum`` (a nonlinear mode, the damper's optimum), ``output``
        and ``study``.  Built anew at each call, so models and effects
        registered since are in it.

    Examples
    --------
    >>> from hbm.scenes import schema
    >>> tables = schema()
    >>> tables["sweep"]["kind"].default, tables["damper.load"]["kind"].default
    ('frequency', 'uniform')
    """
    damper = {"model": Key(one_or_list(_model_names, "a model name"), ("auto",),
                           "contact model: " + ", ".join(f'"{m}"' for m in MODELS) +
                           ", or a list of them (one run each)")}
    damper.update(BASE_DAMPER_KEYS)
    for spec in MODELS.values():
        for key, k in spec.keys.items():
            damper.setdefault(key, k)
    effects = {e.key_name: e.key for e in EFFECTS if e.key_name is not None}
    effects["samples"] = Key(samples_key, OPTIONAL,
                             "AFT samples per period n_t of a multi-harmonic balance (a [structure], or "
                             "effects.harmonics > 1), at least 2 H + 2; default hbm.balance.presets.samples_for(H) "
                             "(32 at H = 1, 512 above)")
    effects["tolerance"] = Key(number(gt=0, lt=1), OPTIONAL,
                               "relative change below which `auto` leaves an effect out; default 1e-6 (the deprecated "
                               "sweep.tolerance where given)")
    out = {"": _FIXED[""], "blade": _FIXED["blade"], "structure": _FIXED["structure"], "damper": damper, "damper.load": _FIXED["damper.load"],
           "effects": effects, "sweep": _FIXED["sweep"], "modes": _FIXED["modes"], "optimum": _FIXED["optimum"], "output": _FIXED["output"]}
    # hbm.scenes.sampling: a grid over, or samples of, the keys above
    out["study"] = study_keys({dot(table, key) for table, keys in out.items() for key in keys})
    return out


def all_keys() -> Iterator[str]:
    """Every ``table.key`` of the schema (top-level keys bare).

    Returns
    -------
    iterator of str
        The dotted names, table by table in the order of ``schema()``.

    Examples
    --------
    >>> from hbm.scenes import all_keys
    >>> keys = list(all_keys())
    >>> keys[0], "damper.load.N" in keys
    ('title', True)
    """
    for table, keys in schema().items():
        for key in keys:
            yield dot(table, key)


__all__ = ["schema", "all_keys", "SUBTABLES", "REQUIRED_TABLES", "BASE_DAMPER_KEYS", "OMEGA_UNITS", "Invalid"]
