# SPDX-License-Identifier: MIT
# The side-by-side measurement of docs/benchmarks.md (issue 34): Blender 3.4's cloth (Debian package
# blender, not a dependency of the build or the tests) on the same scenes, one thread:
#   blender -b -t 1 --python bench/blender_cloth.py -- 21 box       # 484 vertices on a 0.6 m box
#   blender -b -t 1 --python bench/blender_cloth.py -- 29 curtain   # 900 vertices hinged at y = 1
# A 1 m cloth with Blender's cotton preset values, dropped on the box or hinged along one edge and
# released horizontal; 1 s of simulation at 50 frames/s; the wall time and the lowest point printed.
import sys, time
import bpy
args = sys.argv[sys.argv.index('--') + 1:]
side, kind = int(args[0]), args[1]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = 50
scene.frame_start, scene.frame_end = 1, 51
bpy.ops.mesh.primitive_grid_add(x_subdivisions=side, y_subdivisions=side, size=1.0, location=(0.5, 0.5, 0.0))
cloth = bpy.context.active_object
nverts = len(cloth.data.vertices)
if kind == 'curtain':
    # pin the row y = 1 (a vertex group)
    g = cloth.vertex_groups.new(name='pin')
    g.add([v.index for v in cloth.data.vertices if v.co.y > 0.499], 1.0, 'REPLACE')
mod = cloth.modifiers.new('Cloth', 'CLOTH')
s = mod.settings
s.quality = 5
s.mass = 0.3  # Blender cotton preset (per vertex); a physical 0.15 kg/m^2 would make air drag dominate
s.tension_stiffness = s.compression_stiffness = s.shear_stiffness = 15
s.bending_stiffness = 0.5
if kind == 'curtain':
    s.vertex_group_mass = 'pin'
mod.point_cache.frame_start, mod.point_cache.frame_end = 1, 51
if kind == 'box':
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(0.5, 0.5, -0.4))
    bpy.context.active_object.modifiers.new('Collision', 'COLLISION')
t0 = time.perf_counter()
for f in range(1, 52):
    scene.frame_set(f)
t = time.perf_counter() - t0
dg = bpy.context.evaluated_depsgraph_get()
ev = cloth.evaluated_get(dg)
me = ev.to_mesh()
zmin = min((ev.matrix_world @ v.co).z for v in me.vertices)

print(f"BLENDER {kind} vertices {nverts}: {t:.2f} s wall for 1 s simulated (lowest z {zmin:.3f})")
