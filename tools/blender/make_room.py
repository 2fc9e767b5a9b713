"""Builds data/blender_room/ with Blender's own OBJ writer.

A closed 4 x 5 x 3 m room (one box, normals turned inward, coloured walls), a
smooth UV sphere on the floor, a block beside it, a 1 x 1 m emissive plane under
the ceiling facing down, and a camera. Materials are Principled BSDFs: Base
Color for the reflectance, Emission and Emission Strength for the light. The
OBJ and MTL are written by bpy.ops.wm.obj_export with its defaults (no
triangulation, materials on, forward -Z, up Y), as a user would leave them, so
lhr reads what Blender users hand it. OBJ files carry no camera, so the
camera goes into blender_room.scene.json, converted to the OBJ's axes.

Run from the repository root (data/blender_room/README.md):

    blender -b --factory-startup --python tools/blender/make_room.py -- data/blender_room
"""

import json
import math
import os
import sys

import bpy
from bpy_extras.io_utils import axis_conversion
from mathutils import Vector

ROOM = (4.0, 5.0, 3.0)  # x, y, z extent in metres; z is up in Blender
FORWARD_AXIS, UP_AXIS = "NEGATIVE_Z", "Y"  # the exporter's defaults


def principled(name, base, emission=None, strength=0.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    if emission is not None:
        bsdf.inputs["Emission"].default_value = (*emission, 1.0)
        bsdf.inputs["Emission Strength"].default_value = strength
    return mat


def make_room(materials_by_side):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, ROOM[2] / 2))
    room = bpy.context.active_object
    room.name = "Room"
    room.scale = ROOM
    bpy.ops.object.transform_apply(scale=True)
    # Seen from inside: the walls' fronts must face the room.
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.flip_normals()
    bpy.ops.object.mode_set(mode="OBJECT")
    sides = list(materials_by_side)
    for mat in materials_by_side.values():
        room.data.materials.append(mat)
    for poly in room.data.polygons:
        n = poly.normal
        # The inward normal names the wall: a floor faces +z.
        axis = max(range(3), key=lambda i: abs(n[i]))
        side = ("-x", "+x", "-y", "+y", "-z", "+z")[2 * axis + (n[axis] > 0)]
        poly.material_index = sides.index(side)
    return room


def main(out_dir):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    white = principled("White", (0.75, 0.75, 0.72))
    red = principled("RedWall", (0.65, 0.08, 0.06))
    green = principled("GreenWall", (0.12, 0.45, 0.10))
    floor = principled("Floor", (0.55, 0.45, 0.35))
    light = principled("Light", (0.8, 0.8, 0.8), emission=(1.0, 0.9, 0.75), strength=10.0)
    sphere_mat = principled("Sphere", (0.7, 0.7, 0.75))
    block_mat = principled("Block", (0.3, 0.4, 0.65))

    # Inward normals: the wall at x = -2 faces +x, and so on.
    make_room({"+x": red, "-x": green, "+y": white, "-y": white, "+z": floor, "-z": white})

    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.6,
                                         location=(-0.6, 0.6, 0.6))
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    sphere.data.materials.append(sphere_mat)
    bpy.ops.object.shade_smooth()

    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.9, 0.9, 0.4), rotation=(0, 0, math.radians(20)))
    block = bpy.context.active_object
    block.name = "Block"
    block.scale = (0.8, 0.8, 0.8)
    block.data.materials.append(block_mat)

    # 5 cm under the ceiling, turned over so that its front faces the floor.
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, 0.0, ROOM[2] - 0.05),
                                     rotation=(math.pi, 0.0, 0.0))
    lamp = bpy.context.active_object
    lamp.name = "Light"
    lamp.data.materials.append(light)

    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 384, 288
    scene.render.resolution_percentage = 100
    bpy.ops.object.camera_add(location=(1.6, -2.3, 1.7))
    cam = bpy.context.active_object
    cam.name = "Camera"
    target = Vector((-0.2, 0.7, 1.2))
    cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
    cam.data.lens = 18.0
    scene.camera = cam

    os.makedirs(out_dir, exist_ok=True)
    obj_path = os.path.join(out_dir, "blender_room.obj")
    bpy.ops.wm.obj_export(filepath=obj_path, export_triangulated_mesh=False, export_materials=True,
                          forward_axis=FORWARD_AXIS, up_axis=UP_AXIS)
    write_scene_file(os.path.join(out_dir, "blender_room.scene.json"), cam, scene.render, target)


def write_scene_file(path, cam, render, target):
    # The exporter turns Blender's axes into the OBJ's with this matrix.
    to_obj = axis_conversion(to_forward="-Z", to_up="Y").to_4x4()
    world = to_obj @ cam.matrix_world
    eye = world.translation
    up = (to_obj.to_3x3() @ cam.matrix_world.to_3x3() @ Vector((0.0, 1.0, 0.0))).normalized()
    aim = to_obj @ target
    w, h = render.resolution_x, render.resolution_y
    # Sensor fit AUTO: the sensor width spans the longer image side.
    half_height = 0.5 * cam.data.sensor_width * min(w, h) / max(w, h)
    fov_y = 2.0 * math.degrees(math.atan(half_height / cam.data.lens))
    scene_file = {
        "mesh": "blender_room.obj",
        "camera": {
            "eye": [round(c, 6) for c in eye],
            "target": [round(c, 6) for c in aim],
            "up": [round(c, 6) for c in up],
            "fov_y_deg": round(fov_y, 4),
            "width": w,
            "height": h,
        },
    }
    with open(path, "w") as f:
        json.dump(scene_file, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(args) != 1:
        sys.exit("usage: blender -b --factory-startup --python make_room.py -- OUT_DIR")
    main(args[0])
