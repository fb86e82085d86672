// The script's JSON Schema: the one table of every op and key, with its meaning, type and
// default. `ffdtool schema` prints it, the validator checks scripts against it, and
// `ffdtool validate --resolved` fills in its defaults. Adding an op: add its schema here
// (under $defs and in steps.items.oneOf) and its runner to the op table (runner.cpp).
#include "script/schema.h"

namespace ffd {
namespace {

const char* kSchema = R"json({
  "$schema": "https://json-schema.org/draft/2020-12/schema",
  "$id": "https://ffdtool.invalid/script-v1.schema.json",
  "title": "ffdtool script, version 1",
  "description": "A sequence of deformation steps applied to one mesh. Lengths are in the mesh's units, angles in degrees, indices 0-based.",
  "type": "object",
  "required": ["version", "steps"],
  "additionalProperties": false,
  "properties": {
    "version": {"const": 1, "description": "Script format version; must be 1."},
    "description": {"type": "string", "description": "Free text, ignored."},
    "steps": {
      "type": "array",
      "description": "Steps run in order.",
      "items": {
        "oneOf": [
          {"$ref": "#/$defs/lattice"},
          {"$ref": "#/$defs/move"},
          {"$ref": "#/$defs/drag"},
          {"$ref": "#/$defs/remesh"},
          {"$ref": "#/$defs/save"},
          {"$ref": "#/$defs/bcm"},
          {"$ref": "#/$defs/transform_step"}
        ]
      }
    }
  },
  "$defs": {
    "vec3": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3,
             "description": "Three numbers [x, y, z]."},
    "index3": {"type": "array", "items": {"type": "integer"}, "minItems": 3, "maxItems": 3,
               "description": "A lattice index [i, j, k]; i runs along the box's first axis."},
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
           "description": "A text file of mesh vertex indices, one per line ('#' comments); relative to the script's folder."}}}
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
           "fit": {"enum": ["aabb", "obb"], "description": "Fit an axis-aligned or oriented box to the current mesh."},
           "padding": {"type": "number", "minimum": 0, "default": 0.05,
                       "description": "Added on every side, as a fraction of the fitted box's largest extent."},
           "select": {"$ref": "#/$defs/selection", "description": "Fit to these mesh vertices only."}}}
      ]
    },
    "lattice": {
      "type": "object",
      "title": "lattice",
      "description": "Creates a named lattice on top of the warp stack.",
      "required": ["op", "name", "cells"],
      "additionalProperties": false,
      "properties": {
        "op": {"const": "lattice"},
        "name": {"type": "string", "minLength": 1, "description": "Name used by later steps."},
        "basis": {"enum": ["bspline", "bernstein"], "default": "bspline",
                  "description": "bspline: uniform B-spline with fixed influenced and phantom zones (identity outside the box, C^(degree-1) across it). bernstein: Sederberg & Parry's Bézier volume."},
        "degree": {"type": "integer", "minimum": 1, "maximum": 3, "default": 3,
                   "description": "B-spline degree (bspline only; a Bernstein lattice's degree per axis is its cell count)."},
        "box": {"$ref": "#/$defs/box", "default": {"fit": "aabb", "padding": 0.05}},
        "cells": {"type": "array", "items": {"type": "integer", "minimum": 1, "maximum": 1000}, "minItems": 3, "maxItems": 3,
                  "description": "Cells per axis [l, m, n]: B-spline knot spans across the box, or Bernstein degrees."}
      }
    },
    "move": {
      "type": "object",
      "title": "move",
      "description": "Moves lattice control points: listed points by `by`/`to`, or a selection by a transform.",
      "required": ["op", "lattice"],
      "additionalProperties": false,
      "oneOf": [{"required": ["points"]}, {"required": ["select", "transform"]}],
      "properties": {
        "op": {"const": "move"},
        "lattice": {"type": "string", "description": "Name of a lattice created earlier."},
        "points": {"type": "array", "minItems": 1, "items": {
          "type": "object", "required": ["index"], "additionalProperties": false,
          "oneOf": [{"required": ["by"]}, {"required": ["to"]}],
          "properties": {
            "index": {"$ref": "#/$defs/index3"},
            "by": {"$ref": "#/$defs/vec3", "description": "Displacement added to the point's current position."},
            "to": {"$ref": "#/$defs/vec3", "description": "The point's new position."}}}},
        "select": {"$ref": "#/$defs/selection"},
        "transform": {"$ref": "#/$defs/transform"}
      }
    },
    "drag": {
      "type": "object",
      "title": "drag",
      "description": "Direct manipulation (Hsu, Hughes & Kaufman 1992): object points go to targets by the least-norm change of the lattice's movable points.",
      "required": ["op", "lattice", "points"],
      "additionalProperties": false,
      "properties": {
        "op": {"const": "drag"},
        "lattice": {"type": "string"},
        "points": {"type": "array", "minItems": 1, "items": {
          "type": "object", "required": ["to"], "additionalProperties": false,
          "oneOf": [{"required": ["at"]}, {"required": ["vertex"]}],
          "properties": {
            "at": {"$ref": "#/$defs/vec3", "description": "An object point, where it is before this lattice deforms it."},
            "vertex": {"type": "integer", "minimum": 0, "description": "A mesh vertex as the object point."},
            "to": {"$ref": "#/$defs/vec3", "description": "Where the point must go."}}}}
      }
    },
    "remesh": {
      "type": "object",
      "title": "remesh",
      "description": "Adaptive refinement and reversible decimation after the deformations so far (Gain & Dodgson section 4). Polygon faces are triangulated first.",
      "required": ["op"],
      "additionalProperties": false,
      "properties": {
        "op": {"const": "remesh"},
        "theta_max_deg": {"type": "number", "minimum": 0, "maximum": 90, "default": 25.7,
                          "description": "Refine an edge with a deformed endpoint when its deformed endpoint normals diverge by more than this."},
        "theta_min_deg": {"type": "number", "minimum": 0, "maximum": 90, "default": 20.0,
                          "description": "Decimation: endpoint normals diverging by less than this (must be below theta_max_deg)."},
        "l_max": {"oneOf": [{"type": "number", "minimum": 0}, {"type": "string", "const": "auto"}], "default": "auto",
                  "description": "Longest edge where a lattice can act, in mesh units; \"auto\": the smallest lattice cell extent."},
        "max_level": {"type": "integer", "minimum": 1, "maximum": 30, "default": 8,
                      "description": "Refinement level no vertex exceeds; edges it stops are counted."},
        "trigger": {"enum": ["normal", "midpoint"], "default": "normal",
                    "description": "normal: endpoint normal divergence (the paper's choice); midpoint: Greissmair & Purgathofer's midpoint distance, with thresholds L·tan(theta/4) for an edge of length L, or the tolerances below."},
        "split": {"enum": ["edge", "longest"], "default": "edge",
                  "description": "edge: split the edge that triggered (the paper). longest: first split a longer edge of a face on it (Rivara's longest-edge bisection), so repeated refinement of one spot makes no sliver fans; the mesh then follows a distance tolerance with fewer faces."},
        "tolerance": {"type": "number", "minimum": 0,
                      "description": "Midpoint trigger: refine an edge whose chord midpoint stands farther than this from the true deformed surface (a length: bounds the distance to the true surface instead of angles)."},
        "tolerance_min": {"type": "number", "minimum": 0,
                          "description": "Midpoint trigger with a tolerance: decimate below this distance (default tolerance / 2)."}
      }
    },
    "bcm": {
      "type": "object",
      "title": "bcm",
      "description": "Sets up a boundary-constraint modeling editor (Botsch & Kobbelt): the support bends as the solution of Δ^k p = 0 between the fixed surface around it and its handles, which transform steps then move. Bakes the warp stack into the mesh first; factorizes and precomputes the handles' basis functions once.",
      "required": ["op", "name", "support", "handles"],
      "additionalProperties": false,
      "properties": {
        "op": {"const": "bcm"},
        "name": {"type": "string", "minLength": 1,
                 "description": "Name used by transform steps; a later bcm step with the same name replaces the editor."},
        "support": {"$ref": "#/$defs/selection",
                    "description": "The vertices the edit may move, handles included; every other vertex stays fixed."},
        "handles": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/bcm_handle"},
                    "description": "Handle regions inside the support, each moved as a whole by a 9-dof transform; a handle never moved holds its part of the surface in place."},
        "k": {"type": "integer", "minimum": 1, "maximum": 3, "default": 3,
              "description": "Order of Δ^k p = 0: 1 membrane (least area), 2 thin plate (least bending), 3 least curvature variation."},
        "continuity": {"type": "object", "additionalProperties": false,
                       "description": "Boundary smoothness c in [0, k-1], blended continuously (C^0 hinged .. C^(k-1) clamped); each defaults to k-1.",
                       "properties": {
                         "outer": {"type": "number", "minimum": 0, "maximum": 2, "description": "At the support's boundary with the fixed surface."},
                         "inner": {"type": "number", "minimum": 0, "maximum": 2, "description": "At the handles' boundaries."}}},
        "laplacian": {"enum": ["cotan", "uniform", "anisotropic"], "default": "cotan",
                      "description": "cotan: cotangent weights with mixed Voronoi areas on the surface at setup. uniform: 1/valence. anisotropic: cotangent weights on the support's conformal map scaled to equal diameters, so an elongated support bends with even slope (needs a disk-shaped support)."},
        "detail": {"type": "boolean", "default": true,
                   "description": "Multiresolution: edit the support's smooth base (its BCM fairing) and carry the surface detail along as displacements in the base's local frames. false: the support becomes the plain BCM surface."}
      }
    },
    "bcm_handle": {
      "type": "object",
      "required": ["name", "select"],
      "additionalProperties": false,
      "properties": {
        "name": {"type": "string", "minLength": 1, "description": "Name used by transform steps."},
        "select": {"$ref": "#/$defs/selection", "description": "The handle's vertices; all inside the support."}
      }
    },
    "transform_step": {
      "type": "object",
      "title": "transform",
      "description": "Moves a handle of a bcm editor: one pose (`transform`) or a sequence (`frames`), each costing one small dense product. A pose is relative to where the handle was when the editor was set up; `center` defaults to the handle's centroid then.",
      "required": ["op", "editor"],
      "additionalProperties": false,
      "oneOf": [{"required": ["transform"]}, {"required": ["frames"]}],
      "properties": {
        "op": {"const": "transform"},
        "editor": {"type": "string", "description": "Name of a bcm editor set up earlier."},
        "handle": {"type": "string", "description": "Name of the editor's handle; may be left out when it has only one."},
        "transform": {"$ref": "#/$defs/transform"},
        "frames": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/transform"},
                   "description": "Poses applied in order; the handle keeps the last."},
        "save": {"type": "string", "minLength": 1,
                 "description": "Writes the mesh after every frame, '{i}' replaced by the frame's index (0-based); relative to the output folder."}
      }
    },
    "save": {
      "type": "object",
      "title": "save",
      "description": "Writes the current mesh; the format follows the extension (.obj .off .ply .stl).",
      "required": ["op", "path"],
      "additionalProperties": false,
      "properties": {
        "op": {"const": "save"},
        "path": {"type": "string", "minLength": 1, "description": "Relative to the output folder (the folder of -o)."},
        "colors": {"enum": ["mesh", "level"], "default": "mesh",
                   "description": "mesh: the mesh's own vertex colours, if any; level: each vertex's refinement level as a colour (grey = input, blue to red = deeper)."}
      }
    }
  }
})json";

}  // namespace

const nlohmann::json& script_schema() {
  static const nlohmann::json schema = nlohmann::json::parse(kSchema);
  return schema;
}

}  // namespace ffd
