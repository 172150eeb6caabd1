"""Scenes: a study described once in a TOML file, validated, planned and run.

A scene names the blade, the damper (model, bar, normal load), the physical effects in play, the
sweep and the outputs (``docs/scenes.md``; ``python3 -m hbm keys`` lists every key).  Three steps,
each usable alone, each in its own module:

- :func:`load_scene` (``validation``) reads the file and checks it against :func:`schema`
  (``schema``): every problem of the file is reported at once in a :class:`SceneError` naming the
  file, ``table.key``, the value and what is allowed.
- :func:`plan_scene` (``planning``) makes one run per model and load and passes it through the
  effect deciders of :data:`EFFECTS` (``effects``): each decides whether its effect is simulated,
  and why; the model's :class:`ModelSpec` (``models``, the :data:`MODELS` registry) builds the
  contact element.  Physically impossible scenes raise :class:`SceneError`.
- :func:`run_scene` (``running``) computes every run and writes the outputs as it goes;
  ``reporting`` makes the summary, the figure and the command line's text.

Adding a damper model is one :func:`register_model` call; adding an effect one
:func:`register_effect` call (``docs/extending.md``).  Nothing here prints.
"""

from .checks import (OPTIONAL, REQUIRED, Invalid, Key, SceneError, boolean, choice, integer, number,
                     number_list, number_or_name, one_or_list, text)
from .effects import EFFECTS, Effect, EffectSpec, register_effect, unregister_effect
from .models import MODELS, Built, ModelSpec, register_model, unregister_model
from .planning import Plan, RunContext, RunPlan, plan_scene
from .reporting import effect_lines, summary_lines
from .running import Progress, RunResult, SceneResult, columns, output_names, run_scene
from .schema import all_keys, schema
from .validation import Scene, load_scene, parse_override, scene_from_dict

__all__ = ["OPTIONAL", "REQUIRED", "Invalid", "Key", "SceneError", "boolean", "choice", "integer", "number",
           "number_list", "number_or_name", "one_or_list", "text", "EFFECTS", "Effect", "EffectSpec", "register_effect",
           "unregister_effect", "MODELS", "Built", "ModelSpec", "register_model", "unregister_model", "Plan",
           "RunContext", "RunPlan", "plan_scene", "effect_lines", "summary_lines", "Progress", "RunResult",
           "SceneResult", "columns", "output_names", "run_scene", "all_keys", "schema", "Scene", "load_scene",
           "parse_override", "scene_from_dict"]
