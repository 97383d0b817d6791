"""Foxglove's published JSON schemas (github.com/foxglove/schemas, schemas/jsonschema: foxglove.SceneUpdate,
foxglove.PosesInFrame, foxglove.FrameTransforms), restated here for the fields swarmform sends, as the tests' check
of what reaches Foxglove (no network at test time). Their types and bounds are Foxglove's (time: sec >= 0, 0 <= nsec
<= 999999999; LinePrimitive.type 0..2); stricter than Foxglove's in one way: `additionalProperties: false` on every
object, so a misspelled field, which Foxglove would silently ignore, fails. The one field of ours beside Foxglove's,
`tick` at the top of PosesInFrame and FrameTransforms, is allowed by name (Foxglove ignores fields it does not
know)."""


def _obj(**props):
    return {"type": "object", "properties": props, "additionalProperties": False}


def _arr(items):
    return {"type": "array", "items": items}


NUM = {"type": "number"}
STR = {"type": "string"}
BOOL = {"type": "boolean"}
TIME = _obj(sec={"type": "integer", "minimum": 0}, nsec={"type": "integer", "minimum": 0, "maximum": 999999999})
DURATION = _obj(sec={"type": "integer"}, nsec={"type": "integer", "minimum": 0, "maximum": 999999999})
VECTOR3 = _obj(x=NUM, y=NUM, z=NUM)
QUATERNION = _obj(x=NUM, y=NUM, z=NUM, w=NUM)
POSE = _obj(position=VECTOR3, orientation=QUATERNION)
COLOR = _obj(r=NUM, g=NUM, b=NUM, a=NUM)
ARROW = _obj(pose=POSE, shaft_length=NUM, shaft_diameter=NUM, head_length=NUM, head_diameter=NUM, color=COLOR)
CUBE = _obj(pose=POSE, size=VECTOR3, color=COLOR)
SPHERE = _obj(pose=POSE, size=VECTOR3, color=COLOR)
CYLINDER = _obj(pose=POSE, size=VECTOR3, bottom_scale=NUM, top_scale=NUM, color=COLOR)
LINE = _obj(type={"enum": [0, 1, 2]}, pose=POSE, thickness=NUM, scale_invariant=BOOL, points=_arr(VECTOR3),
            color=COLOR, colors=_arr(COLOR), indices=_arr({"type": "integer", "minimum": 0}))
TEXT = _obj(pose=POSE, billboard=BOOL, font_size=NUM, scale_invariant=BOOL, color=COLOR, text=STR)
ENTITY = _obj(timestamp=TIME, frame_id=STR, id=STR, lifetime=DURATION, frame_locked=BOOL,
              metadata=_arr(_obj(key=STR, value=STR)), arrows=_arr(ARROW), cubes=_arr(CUBE), spheres=_arr(SPHERE),
              cylinders=_arr(CYLINDER), lines=_arr(LINE), texts=_arr(TEXT))
SCHEMAS = {
    "foxglove.SceneUpdate": _obj(deletions=_arr(_obj(timestamp=TIME, type={"enum": [0, 1]}, id=STR)),
                                 entities=_arr(ENTITY)),
    "foxglove.PosesInFrame": _obj(timestamp=TIME, frame_id=STR, poses=_arr(POSE), tick={"type": "integer"}),
    "foxglove.FrameTransforms": _obj(transforms=_arr(_obj(timestamp=TIME, parent_frame_id=STR, child_frame_id=STR,
                                                          translation=VECTOR3, rotation=QUATERNION)),
                                     tick={"type": "integer"}),
}


def validate(value, schema, where="$"):
    """Raises AssertionError naming the path of the first field of `value` that `schema` refuses. The subset of
    JSON Schema the schemas here and the server's advertised ones use: type, properties, additionalProperties,
    items, enum, minimum, maximum (no library: Debian 12's python3 has none installed by scripts/setup)."""
    kind = schema.get("type")
    checks = {"object": lambda v: isinstance(v, dict), "array": lambda v: isinstance(v, list),
              "string": lambda v: isinstance(v, str), "boolean": lambda v: isinstance(v, bool),
              "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
              "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)}
    if kind is not None and not checks[kind](value):
        raise AssertionError(f"{where}: expected {kind}, got {value!r:.80}")
    if "enum" in schema and value not in schema["enum"]:
        raise AssertionError(f"{where}: {value!r} not one of {schema['enum']}")
    if "minimum" in schema and value < schema["minimum"]:
        raise AssertionError(f"{where}: {value} < {schema['minimum']}")
    if "maximum" in schema and value > schema["maximum"]:
        raise AssertionError(f"{where}: {value} > {schema['maximum']}")
    if isinstance(value, dict):
        props = schema.get("properties", {})
        for k, v in value.items():
            if k in props:
                validate(v, props[k], f"{where}.{k}")
            elif schema.get("additionalProperties") is False:
                raise AssertionError(f"{where}: field '{k}' is not in the schema (Foxglove would ignore it)")
            elif isinstance(schema.get("additionalProperties"), dict):
                validate(v, schema["additionalProperties"], f"{where}.{k}")
    if isinstance(value, list) and "items" in schema:
        for i, v in enumerate(value):
            validate(v, schema["items"], f"{where}[{i}]")
