"""Every field of the bound C++ structs is reachable from Python. Reads the public headers:
a field added in C++ without its line in python/src/*.cpp fails here, naming the field."""
import os
import re

import pytest

import ncp

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def struct_fields(header, struct):
    """Names of the data members of `struct` in `header` (declarations ending in ';' at
    the struct's indentation, several declarators per line allowed; no member functions)."""
    with open(os.path.join(ROOT, header)) as f:
        text = f.read()
    body = re.search(r"^struct " + struct + r" \{\n(.*?)^\};", text, re.S | re.M).group(1)
    body = re.sub(r"//[^\n]*", "", body)
    names = []
    for statement in body.split(";"):
        statement = " ".join(statement.split())
        if not statement or "(" in statement.split("=")[0] and "std::function" not in statement:
            continue
        if statement.startswith(("struct ", "enum ", "using ", "static ")):
            continue
        for declarator in re.split(r",(?![^<(]*[>)])", statement):
            name = re.findall(r"(\w+)\s*(?:=.*)?$", declarator.split("=")[0].strip())
            if name:
                names.append(name[-1])
    return names


def test_every_ncp_option_is_a_keyword_argument():
    missing = set(struct_fields("ncp/include/ncp/solver.hpp", "Options")) - set(ncp.Options._fields)
    assert not missing, f"add to BindOptions in python/src/ncp_module.cpp: {sorted(missing)}"


def test_every_ncp_summary_field_is_readable():
    missing = set(struct_fields("ncp/include/ncp/solver.hpp", "Summary")) - set(ncp.Summary._fields)
    assert not missing, f"add to BindSummary in python/src/ncp_module.cpp: {sorted(missing)}"
    missing = set(struct_fields("ncp/include/ncp/solver.hpp", "IterationRecord")) - set(ncp.IterationRecord._fields)
    assert not missing, f"add to BindSummary in python/src/ncp_module.cpp: {sorted(missing)}"


def test_every_contact_record_and_summary_field_is_returned():
    contact = pytest.importorskip("contact")
    # Returned under other keys: the step's solver status as a list, the summary's status and
    # message in result.summary, the records as result.records, u as final_displacement_free.
    # Not returned: predicted_cost, auto's prediction (a struct; in contact-sim's JSON as
    # predicted_*_step_seconds and auto_choice).
    special = {"solver_status", "status", "message", "step_method", "records", "u", "predicted_cost",
               "kinematics", "material_model"}  # (strings: in result.summary, not columns)
    # C++ fields whose record carries the name of the steps.csv column.
    renamed = {"kinetic": "kinetic_energy", "strain": "strain_energy", "tangent_force_sum": "friction_force_sum"}
    fields = {renamed.get(f, f) for f in struct_fields("contact/include/contact/dynamics_types.hpp", "StepRecord")}
    missing = fields - special - set(contact.STEP_FIELDS)
    assert not missing, f"add to StepColumns in python/src/contact_module.cpp: {sorted(missing)}"
    missing = (set(struct_fields("contact/include/contact/dynamics.hpp", "DynamicSummary")) - special
               - set(contact.SUMMARY_FIELDS))
    assert not missing, f"add to SummaryColumns in python/src/contact_module.cpp: {sorted(missing)}"


@pytest.mark.parametrize("enum", ["NcpFunction", "LinearSolverType", "TerminationType"])
def test_every_enumerator_is_bound(enum):
    """Each enumerator of ncp/types.hpp has its Python value (a binding that stopped one
    short once left TerminationType.TIME_LIMIT out)."""
    with open(os.path.join(ROOT, "ncp/include/ncp/types.hpp")) as f:
        text = f.read()
    body = re.search(r"^enum class " + enum + r" \{\n(.*?)^\};", text, re.S | re.M).group(1)
    body = re.sub(r"//[^\n]*", "", body)
    enumerators = re.findall(r"^\s*k(\w+),", body, re.M)
    bound = getattr(ncp, enum).__members__
    assert len(bound) == len(enumerators), f"{enum}: C++ {enumerators}, Python {sorted(bound)}"
