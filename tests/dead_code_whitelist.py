"""Names the dead-code check (tests/acceptance/test_dead_code.py, vulture) cannot see being used, each with why: read
by another program (Exudyn, numba, mkdocs, setup.py), by Python's own protocols, or written to files through
dataclass fields. A name listed here that is not used that way is dead code: remove it from both."""

# ruff: noqa
import docs_hooks

import pchute_exudyn
from pchute_exudyn import environment
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.engine import solver
from pchute_exudyn.methods.equilibrium import EquilibriumPoint
from pchute_exudyn.methods.sp import balance, memory
from pchute_exudyn.physics import aerodynamics, air, compiled, gravity, kinematics, planet
from pchute_exudyn.results import result, summary

docs_hooks.on_files, docs_hooks.on_page_content  # mkdocs calls its hooks by name
pchute_exudyn.__getattr__, pchute_exudyn.__dir__  # PEP 562: the package's names imported when first used
EquilibriumPoint  # found by the method table's discovery (methods.register_builtin), as every method class
environment.SKIP_KERNEL_BUILD  # read by setup.py (which cannot import the package) by its value
NewCase.main_mass  # set by keyword from `pchute new --main-mass`, read through dataclasses.fields
# each canopy's size, read per canopy as getattr(c, f"{which}_drag_area") and alike (authoring.rocket, rocket_start)
NewCase.drogue_drag_area, NewCase.main_drag_area, NewCase.drogue_diameter, NewCase.main_diameter
NewCase.drogue_drag_coefficient, NewCase.main_drag_coefficient
compiled.CompiledKernel.__wrapped__  # inspect.signature and functools follow it to the Python function

# Exudyn reads these: its settings objects' fields, its user functions' parameter names
_.writePeriod, _.startTime, _.endTime, _.numberOfSteps, _.verboseMode, _.automaticStepSize
_.useLieGroupIntegration, _.computeEndOfStepAccelerations, _.spectralRadius, _.lieGroupAddTangentOperator
_.adaptiveStep, _.useModifiedNewton, _.currentStepSize, _.itemNumber, _.load_vector
_.output_dir  # numba's pycc CC: where it writes the module

# A layout names each of its positions, the ones only its neighbours' readers use too
memory.LAYOUT_STIFFNESS, memory.SOLVED_VELOCITY, memory.SOLVED_KAPPA
aerodynamics.VALUE_FORCE, aerodynamics.VALUE_MOMENT, air.AIR_COLUMNS, gravity.NORMAL_COLUMNS, planet.FRAME_COLUMNS
kinematics.ROW_ANGULAR_VELOCITY
balance.MassTerm.reference_velocity  # unpacked by position (stepping._mass_term writes the same three)
memory.Memory.fill_rate  # a named cell of the memory row the kernel reads by its constant (stepping.sp_rk_stage)

# Fields written to files through dataclasses.fields / asdict, and API for users
summary.StartEvent.moving_with, _.clearance_after, _.line_stretch_time, _.line_stretch_speed, _.knacke_opening_load, _.opening_stage, _.max_airspeed_deg, _.rms_airspeed_deg, _.amplitude_airspeed_deg
result.Result.to_pandas  # the documented way to a DataFrame (docs/results.md)

# pytest finds these by name: hooks, fixtures (autouse, or asked for by a test's parameter), module marks
_.pytest_runtest_call, _._release_locks, _.fixed_method, _.pytestmark
# run by name in a process of its own (tests/acceptance/test_line_law_plants.py)
_.check_every_form
# Selenium reads it: the Chromium binary the driver starts (tests/browser.py)
_.binary_location
