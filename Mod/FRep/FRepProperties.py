"""Registry parameters as FreeCAD properties: which property type, its name, tooltip, default,
and reading a value back as the plain number, vector or text frepcore expects.

Nothing here is per node type: every feature class is generated from the registry.
"""

import os

import FreeCAD

from FRepPaths import frepcore

PARAM_GROUP = "FRep"
INPUT_GROUP = "FRep inputs"


def property_name(param_name):
    """Registry names are snake_case, FreeCAD's are CamelCase: major_radius -> MajorRadius."""
    return "".join(part[:1].upper() + part[1:] for part in param_name.split("_"))


def type_class_name(type_id):
    """blend_union -> BlendUnion: the feature's class and default object name."""
    return property_name(type_id)


def property_type(param):
    t, unit = param["type"], param["unit"]
    if t == "real":
        if unit == "length":
            nonnegative = param["min"] is not None and param["min"] >= 0
            return "App::PropertyLength" if nonnegative else "App::PropertyDistance"
        if unit == "angle":
            return "App::PropertyAngle"
        return "App::PropertyFloat"
    if t == "integer":
        return "App::PropertyInteger"
    if t == "boolean":
        return "App::PropertyBool"
    if t == "vector3":
        return "App::PropertyVectorDistance" if unit == "length" else "App::PropertyVector"
    if t == "matrix3x4":
        return "App::PropertyMatrix"
    if t == "choice":
        return "App::PropertyEnumeration"
    if t == "points":
        return "App::PropertyVectorList"
    if t == "text":
        return "App::PropertyFile" if param.get("file") else "App::PropertyString"
    raise ValueError("FRep: no FreeCAD property for parameter type '%s'" % t)


UNIT_SUFFIX = {"length": " mm", "angle": " deg", "": ""}


def tooltip(param):
    return "%s Allowed: %s%s." % (param["doc"], param["allowed"], UNIT_SUFFIX[param["unit"]])


def add_param_property(obj, param):
    name = property_name(param["name"])
    if name in obj.PropertiesList:
        return
    obj.addProperty(property_type(param), name, PARAM_GROUP, tooltip(param))
    if param["type"] == "choice":
        setattr(obj, name, list(param["choices"]))
    set_value(obj, param, param["default"])


def set_value(obj, param, value):
    name = property_name(param["name"])
    t = param["type"]
    if t == "vector3":
        setattr(obj, name, FreeCAD.Vector(*value))
    elif t == "matrix3x4":
        m = FreeCAD.Matrix()
        m.A = list(value) + [0.0, 0.0, 0.0, 1.0]
        setattr(obj, name, m)
    elif t == "boolean":
        setattr(obj, name, bool(value))
    elif t == "integer":
        setattr(obj, name, int(value))
    elif t == "points":
        setattr(obj, name, [FreeCAD.Vector(*p) for p in value])
    else:
        setattr(obj, name, value)


def get_value(obj, param):
    """The property's value in frepcore's terms (mm, degrees, tuples, text)."""
    v = getattr(obj, property_name(param["name"]))
    t = param["type"]
    if t == "real":
        return float(v.Value) if hasattr(v, "Value") else float(v)
    if t == "integer":
        return int(v)
    if t == "boolean":
        return bool(v)
    if t == "vector3":
        return (v.x, v.y, v.z)
    if t == "matrix3x4":
        return tuple(v.A[:12])
    if t == "points":
        return [(p.x, p.y, p.z) for p in v]
    if t == "text" and param.get("file") and v and not os.path.isabs(v):
        # A relative file name is read from the document's folder (the model format's rule).
        folder = os.path.dirname(obj.Document.FileName) if obj.Document.FileName else ""
        return os.path.join(folder or os.getcwd(), str(v))
    return str(v)


def in_property_terms(message, label, info):
    """frepcore's "Label (type): parameter 'name' ..." as "Label: property 'Name' ...", the
    words the user sees in the property editor (whole-node checks such as a formula's)."""
    head = "%s (%s): " % (label, info["type"])
    if not message.startswith(head):
        return message
    rest = message[len(head):]
    for param in info["params"]:
        quoted = "parameter '%s'" % param["name"]
        if rest.startswith(quoted):
            rest = "property '%s'" % property_name(param["name"]) + rest[len(quoted):]
            break
    return "%s: %s" % (label, rest)


def value_text(param, value):
    unit = UNIT_SUFFIX[param["unit"]]
    if isinstance(value, list):
        return "%d points" % len(value)
    if isinstance(value, tuple):
        return "(%s)%s" % (", ".join("%g" % x for x in value), unit)
    if isinstance(value, float):
        return "%g%s" % (value, unit)
    return str(value) if value != "" else '""'


def check_value(obj, type_id, param):
    """Reads a parameter; raises ValueError naming the object, the property and what is allowed."""
    value = get_value(obj, param)
    problem = frepcore.check_param(type_id, param["name"], value)
    if problem:
        # The registry says "<value> is out of range; allowed: (0, inf)" in its own names;
        # the user sees the property, its value in FreeCAD units and the allowed range.
        # (or, with no value to name, "is empty; allowed: ...")
        core = problem[3:] if problem.startswith("is ") else \
            problem.split(" is ", 1)[1] if " is " in problem else problem
        raise ValueError("%s: property '%s' = %s is %s%s" % (
            obj.Label, property_name(param["name"]), value_text(param, value), core,
            UNIT_SUFFIX[param["unit"]]))
    return value
