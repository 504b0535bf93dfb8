"""rov_tether: simulated ROV tethers from Python (docs/python.md).

    import rov_tether
    world = rov_tether.World.from_scenario("scenarios/pillar_wrap.yaml")   # or rov_tether.World({...})
    world.advance_to(10.0)
    tether = world.tethers[0]
    tether.positions          # N x 3 [m], spool first
    tether.segment_tension    # N - 1 [N], spool first
    world.topology()          # wrap turns, contact angles, capstan ratios, linking numbers

    camera = rov_tether.Camera(640, 480, K=[400, 0, 319.5, 0, 400, 239.5, 0, 0, 1])
    mask, depth = camera.render(world, position=[0, -5, -1], orientation=[x, y, z, w])

The compiled parts are rov_tether._core (src/python/module.cpp), loaded on first use of World or Tether, and
rov_tether._camera (camera_module.cpp, with OpenCV), loaded on first use of Camera: in a
catkin workspace the message modules (rov_tether.msg, rov_tether.srv) live in the same package, and a node
that imports only those does not load the simulator.
"""
__all__ = ["Camera", "Tether", "World"]


def __getattr__(name):
    if name == "Camera":  # its own module, which loads OpenCV
        from . import _camera

        return _camera.Camera
    if name in __all__:
        from . import _core

        return getattr(_core, name)
    raise AttributeError("module 'rov_tether' has no attribute '%s'" % name)


def __dir__():
    # What tab completion and dir() list: the lazily loaded names too, and the message modules beside them.
    return sorted(set(globals()) | set(__all__))
