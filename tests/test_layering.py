"""The Python layer's import graph, read from the sources with ``ast`` (docs/architecture.md,
"Python layers"): every module of python/phmech is in the table below, which lists them bottom-up,
and a module imports only modules listed above it -- so the graph is a DAG that respects the
layer order -- with no phmech import inside a function or class to hide a cycle (third-party
optional imports there, matplotlib or xarray, are fine). Only the kernel's wrappers, the core
layer and two modules whose whole job is a core kernel import the C extension ``phmech._core``.
"""
import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "python" / "phmech"

LAYERS = ("kernel", "describe", "results", "core", "compose", "api", "extras", "package")

#: (module, layer, may import _core): bottom-up; a module may import only the modules above it
TABLE = (
    ("_errors", "kernel", True),        # exceptions, warning classes, outside_stacklevel
    ("_codes", "kernel", True),         # the core's code tables (_core.codes()) and stateless kernels
    ("_checks", "kernel", False),       # argument checks, one message style
    ("se3", "kernel", True),            # SE(3)/SO(3) kernels of the core
    ("_lawbase", "describe", False),    # the law algebra: _Law, Constant, Sum, Product, Function, core tuples
    ("laws", "describe", False),        # time laws: the shapes, piecewise polynomials, law_from_data
    ("pairs", "describe", False),       # pair classes from the core's pair table
    ("actuators", "describe", False),   # Effort, PD, Spring
    ("components", "describe", False),  # friction, motors, controllers with internal states
    ("section", "describe", False),     # Material, Section, BeamProperties
    ("frames", "describe", False),      # Frame, Body, FlexibleLink, MeshChoice, ModalChoice
    ("sensors", "describe", False),     # JointSensor, FrameSensor, TipDeflection, LinkStrain
    ("controllers", "describe", False),  # SampledController, its outputs, the held values
    ("description", "describe", False),  # ModelDescription: the rows
    ("graphs", "describe", False),      # graphs and incidence matrices
    ("analysis", "describe", False),    # spectra, MAC, mode energies and labels
    ("fidelity", "describe", False),    # rigid and modal link reductions (NumPy)
    ("io", "describe", False),          # model files: recording, codecs, JSON
    ("_placement", "describe", False),  # tree placement of the initial configuration
    ("_links", "describe", False),      # LinkBuilder: add_flexible_link
    ("_builder", "describe", False),    # Builder: the other add_* methods
    ("_resultfile", "results", False),  # results as xarray / netCDF / pandas
    ("results", "results", False),      # SimulationResult, ModesResult, StaticResult, load_result
    ("_marshal", "core", True),         # a description's columns for _core.model_new
    ("topology", "core", True),         # loop closure, redundant rows, initial state
    ("planar", "core", True),           # planar scene detection
    ("_run", "core", False),            # run monitoring: progress, cost, checkpoints, quality
    ("_sampled", "core", False),        # sampled controllers in a run: instants, calls, sensors
    ("postprocess", "core", True),      # stress resultants, constraint residuals
    ("linear", "core", False),          # LinearPortHamiltonian
    ("_model", "core", False),          # the built model: initial state, core model, warnings
    ("_modes", "core", True),           # Mechanism.modes and its equilibrium check
    ("_linearize", "core", True),       # Mechanism.linearize
    ("_statics", "core", True),         # Mechanism.static and free motions
    ("_simulate", "core", True),        # Mechanism.simulate: options, run, result
    ("_reduction", "compose", False),   # link-alone analyses behind modal links
    ("_modal", "compose", False),       # modal link assembly on a mechanism
    ("mesh", "compose", False),         # element counts from a band; Mechanism.sized
    ("mechanism", "api", False),        # Mechanism = Builder + the analyses; load
    ("timoshenko", "extras", False),    # Timoshenko beam reference
    ("mixed", "extras", True),          # Golo's mixed element (its own core kernels)
    ("sweep", "extras", False),         # parameter sweeps
    ("studies", "extras", False),       # the paper's studies
    ("_plotdata", "extras", False),     # what plot draws, in world coordinates (NumPy)
    ("_plotaxes", "extras", False),     # plot's Axes, artists and plotly traces
    ("plot", "extras", False),          # matplotlib / plotly
    ("fmu", "extras", False),           # FMU export
    ("_urdfparse", "extras", False),    # a URDF file read: tree, inertias, joint frames
    ("urdf", "extras", False),          # URDF import
    ("__init__", "package", True),      # the public names (info, blas_threads call the core)
)
ORDER = {m: i for i, (m, _, _) in enumerate(TABLE)}
LAYER = {m: layer for m, layer, _ in TABLE}
CORE_OK = {m for m, _, ok in TABLE if ok}


def _imports(tree: ast.Module):
    """(phmech module imported, line, at module level) for every import in ``tree``; module
    level includes ``if``/``try`` blocks at the top, not function or class bodies."""
    out = []

    def visit(node, top):
        for ch in ast.iter_child_nodes(node):
            nested = not top or isinstance(ch, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef,
                                                ast.Lambda))
            if isinstance(ch, ast.ImportFrom):
                if ch.level == 1:
                    names = [ch.module] if ch.module else [a.name for a in ch.names]
                elif ch.level == 0 and ch.module and ch.module.split(".")[0] == "phmech":
                    parts = ch.module.split(".")
                    names = [parts[1]] if len(parts) > 1 else [a.name for a in ch.names]
                else:
                    names = []
                out.extend((n.split(".")[0], ch.lineno, top) for n in names)
            elif isinstance(ch, ast.Import):
                out.extend((a.name.split(".")[1], ch.lineno, top) for a in ch.names
                           if a.name.startswith("phmech."))
            visit(ch, top and not nested)
    visit(tree, True)
    return out


def import_graph(src: Path = SRC) -> dict:
    """module -> [(imported phmech module, line, at module level)] for every module in ``src``."""
    return {p.stem: _imports(ast.parse(p.read_text(encoding="utf-8"), str(p)))
            for p in sorted(src.glob("*.py"))}


def violations(graph: dict) -> list:
    """What breaks the layering: modules missing from the table, imports of a module not above
    the importer, phmech imports inside functions or classes, _core imported outside CORE_OK."""
    out = [f"{m}.py is not in tests/test_layering.py's TABLE" for m in graph if m not in ORDER]
    out += [f"{m} is in TABLE but python/phmech/{m}.py does not exist" for m in ORDER if m not in graph]
    for m, imps in graph.items():
        for dep, line, top in imps:
            where = f"python/phmech/{m}.py:{line}"
            if dep == "_core":
                if m not in CORE_OK:
                    out.append(f"{where}: {m} ({LAYER.get(m)}) imports _core (only kernel "
                               f"wrappers and the core layer may)")
            elif dep == "__version__":
                out.append(f"{where}: import __version__ from phmech._errors")
            elif not top:
                out.append(f"{where}: {m} imports {dep} inside a function or class")
            elif dep in ORDER and m in ORDER and ORDER[dep] >= ORDER[m]:
                out.append(f"{where}: {m} ({LAYER[m]}) imports {dep} ({LAYER[dep]}), which is "
                           f"not above it in the layer table")
    return out


def test_the_table_lists_the_layers_bottom_up():
    layers = [LAYERS.index(layer) for _, layer, _ in TABLE]
    assert layers == sorted(layers)
    assert len(ORDER) == len(TABLE)


def test_the_import_graph_follows_the_layers():
    assert violations(import_graph()) == []


def test_an_upward_import_is_caught(tmp_path):
    """The check itself: plant an import of the api layer in the kernel, a function-level
    import, and a _core import in the describe layer, into a copy of the sources."""
    for p in SRC.glob("*.py"):
        (tmp_path / p.name).write_text(p.read_text(encoding="utf-8"), encoding="utf-8")
    assert violations(import_graph(tmp_path)) == []
    checks = tmp_path / "_checks.py"
    checks.write_text(checks.read_text() + "\nfrom .mechanism import Mechanism\n")
    laws = tmp_path / "laws.py"
    laws.write_text(laws.read_text() + "\n\ndef f():\n    from . import results\n"
                    "\n\nfrom . import _core\n")
    found = violations(import_graph(tmp_path))
    assert any("_checks (kernel) imports mechanism (api)" in v for v in found), found
    assert any("laws imports results inside a function" in v for v in found), found
    assert any("laws (describe) imports _core" in v for v in found), found



def test_meson_installs_every_module():
    """A module missing from meson.build's install list is in the source tree but not in the
    wheel or in .venv (a fresh `make build`)."""
    meson = (SRC.parents[1] / "meson.build").read_text(encoding="utf-8")
    missing = [m for m in ORDER if f"'python/phmech/{m}.py'" not in meson]
    assert missing == [], f"add to meson.build (py.install_sources): {missing}"
