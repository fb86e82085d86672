// The script's JSON Schema: the shared grammar's types (vectors, selections, transforms,
// boxes) written here once, and every op's part generated from its key table (op.h). The
// validator checks scripts against it, `validate --resolved` fills in its defaults and
// `ffdtool schema` prints it. Adding an op needs nothing here. The grammar's defaults
// (a transform's translate and scale, a fitted box's padding) are those of Transform{}
// and BoxSpec{}; script_test checks that they agree.
#include "script/schema.h"

#include "script/op.h"

namespace ffd {
namespace {

using json = nlohmann::json;

const char* kGrammar = R"json({
    "vec3": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3,
             "description": "Three numbers [x, y, z]."},
    "index3": {"type": "array", "items": {"type": "integer"}, "minItems": 3, "maxItems": 3,
               "description": "A lattice index [i, j, k]; i runs along the box's first axis."},
    "point_index": {
      "description": "A control point: [i, j, k] on a lattice, or its number n for scattered points (rbf, idw) and cage vertices.",
      "oneOf": [{"$ref": "#/$defs/index3"}, {"type": "integer", "minimum": 0}]
    },
    "points": {
      "description": "Positions of control points: a list of [x, y, z], a file of them (an OBJ's v lines or x y z lines; relative to the script's folder), or the current positions of selected mesh vertices.",
      "oneOf": [
        {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/vec3"}},
        {"type": "object", "title": "file", "required": ["file"], "additionalProperties": false,
         "properties": {"file": {"type": "string"}}},
        {"type": "object", "title": "select", "required": ["select"], "additionalProperties": false,
         "properties": {"select": {"$ref": "#/$defs/selection"}}}
      ]
    },
    "selection_part": {
      "oneOf": [
        {"type": "object", "title": "indices", "required": ["indices"], "additionalProperties": false,
         "properties": {"indices": {"type": "array", "minItems": 1,
           "items": {"oneOf": [{"type": "integer", "minimum": 0}, {"$ref": "#/$defs/index3"}]},
           "description": "Mesh vertex indices, or lattice indices [i, j, k]."}}},
        {"type": "object", "title": "sphere", "required": ["sphere"], "additionalProperties": false,
         "properties": {"sphere": {"type": "object", "required": ["center", "radius"], "additionalProperties": false,
           "description": "Everything within `radius` of `center` (boundary included).",
           "properties": {"center": {"$ref": "#/$defs/vec3"}, "radius": {"type": "number", "minimum": 0}}}}},
        {"type": "object", "title": "box", "required": ["box"], "additionalProperties": false,
         "properties": {"box": {"type": "object", "required": ["min", "max"], "additionalProperties": false,
           "description": "Everything inside the axis-aligned box [min, max] (faces included).",
           "properties": {"min": {"$ref": "#/$defs/vec3"}, "max": {"$ref": "#/$defs/vec3"}}}}},
        {"type": "object", "title": "near", "required": ["near"], "additionalProperties": false,
         "properties": {"near": {"$ref": "#/$defs/vec3", "description": "The single nearest element (ties: lowest index)."}}},
        {"type": "object", "title": "file", "required": ["file"], "additionalProperties": false,
         "properties": {"file": {"type": "string",
           "description": "A text file of mesh vertex indices, one per line ('#' comments); relative to the script's folder."}}},
        {"type": "object", "title": "marker", "required": ["marker"], "additionalProperties": false,
         "properties": {"marker": {"type": "string", "minLength": 1,
           "description": "Volume meshes: the nodes of a boundary marker's or physical group's elements, by name (an SU2 MARKER_TAG, a Gmsh physical name or number, an OpenFOAM patch)."}}}
      ]
    },
    "selection": {
      "description": "Mesh vertices or lattice points; a list of selections is their union. Lattice points are chosen among the movable ones, by their current positions.",
      "oneOf": [
        {"$ref": "#/$defs/selection_part"},
        {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/selection_part"}}
      ]
    },
    "transform": {
      "type": "object",
      "additionalProperties": false,
      "description": "A 9-dof affine map p -> center + R·S·(p - center) + translate.",
      "properties": {
        "translate": {"$ref": "#/$defs/vec3", "default": [0, 0, 0]},
        "rotate": {"type": "object", "required": ["axis", "degrees"], "additionalProperties": false,
                   "description": "Rotation by `degrees` about `axis` (right-hand rule).",
                   "properties": {"axis": {"$ref": "#/$defs/vec3"}, "degrees": {"type": "number"}}},
        "scale": {"oneOf": [{"type": "number"}, {"$ref": "#/$defs/vec3"}], "default": 1,
                  "description": "Uniform factor, or one factor per axis."},
        "center": {"$ref": "#/$defs/vec3",
                   "description": "Fixed point of rotation and scale; defaults to the centroid of what is selected."}
      }
    },
    "box": {
      "description": "The lattice's parallelepiped.",
      "oneOf": [
        {"type": "object", "title": "min/max", "required": ["min", "max"], "additionalProperties": false,
         "properties": {"min": {"$ref": "#/$defs/vec3"}, "max": {"$ref": "#/$defs/vec3"}}},
        {"type": "object", "title": "origin/axes", "required": ["origin", "axes"], "additionalProperties": false,
         "properties": {"origin": {"$ref": "#/$defs/vec3"},
                        "axes": {"type": "array", "minItems": 3, "maxItems": 3, "items": {"$ref": "#/$defs/vec3"},
                                 "description": "The three edge vectors from the origin corner."}}},
        {"type": "object", "title": "fit", "required": ["fit"], "additionalProperties": false,
         "properties": {
           "fit": {"enum": ["aabb", "obb", "min_volume"], "description": "Fit a box to the current mesh: aabb, axis-aligned; obb, along the principal components of the vertices (Gottschalk's OBB, what Ono et al. use); min_volume, the box of least volume (CGAL's optimal bounding box, slower)."},
           "padding": {"type": "number", "minimum": 0, "default": 0.05,
                       "description": "Added on every side, as a fraction of the fitted box's largest extent."},
           "select": {"$ref": "#/$defs/selection", "description": "Fit to these mesh vertices only."}}}
      ]
    }
})json";

// The op's name in $defs: its own, or "<op>_step" where a grammar type has that name.
std::string def_name(const json& defs, const std::string& op) { return defs.contains(op) ? op + "_step" : op; }

json build_schema() {
  json defs = json::parse(kGrammar);
  json steps = json::array();
  for (const OpInfo* op : op_table()) {
    const std::string name = def_name(defs, op->name());
    defs[name] = op->schema();
    steps.push_back({{"$ref", "#/$defs/" + name}});
  }
  return {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
          {"$id", "https://ffdtool.invalid/script-v1.schema.json"},
          {"title", "ffdtool script, version 1"},
          {"description",
           "A sequence of deformation steps applied to one mesh. Lengths are in the mesh's units, angles in degrees, "
           "indices 0-based."},
          {"type", "object"},
          {"required", {"version", "steps"}},
          {"additionalProperties", false},
          {"properties",
           {{"version", {{"const", 1}, {"description", "Script format version; must be 1."}}},
            {"description", {{"type", "string"}, {"description", "Free text, ignored."}}},
            {"allow_inverted",
             {{"type", "boolean"},
              {"default", false},
              {"description",
               "Volume meshes: write the result even if it has inverted cells (a warning names them). By default "
               "such a run fails with exit 2 and writes nothing. Also the run's --allow-inverted flag."}}},
            {"steps", {{"type", "array"}, {"description", "Steps run in order."}, {"items", {{"oneOf", steps}}}}}}},
          {"$defs", defs}};
}

}  // namespace

const nlohmann::json& script_schema() {
  static const nlohmann::json schema = build_schema();
  return schema;
}

}  // namespace ffd
