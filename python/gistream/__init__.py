"""gistream: a small Python client of gistreamd.

    import gistream
    with gistream.Client("127.0.0.1:50051") as client:
        scene = client.load_scene("cornell_box")
        frame = client.render(scene.scene_id, solver="implicit_visibility", size=(256, 256))
        open("box.png", "wb").write(frame.image)
        with client.session(scene.scene_id, solver="direct", size=(320, 240)) as session:
            session.update(camera=gistream.look_at((1, 0.3, 0.2), (0.2, 0.2, 0.2)))
            # glTF metallic-roughness (GGX): a material made glossy
            session.update(material=gistream.material_change(0, metallic=1.0, roughness=0.3))
            for frame in session.frames(10):
                print(frame.frame_number, frame.last_update_seq, frame.total_ms)

A session on a scene the client loaded moves by itself when its server
drains (SIGTERM) or dies: the scene is loaded again through the same
address (behind a balancer: another server; `affinity=` keeps one piece of
work on one server), the session reopened and its updates sent again;
`session.moves` lists the moves. `resume=False` turns this off.

A server with TLS and tokens (gistreamd --tls-cert ... --auth-tokens ...):

    client = gistream.Client("render.example:50051", token="...",  # or $GISTREAM_TOKEN
                             credentials=gistream.tls_credentials(ca="ca.crt"))

The generated stubs (gistream.v1.gistream_pb2, gistream_pb2_grpc) come
from the build (CMake writes the package into build/python); everything
the API offers is there, this module only makes the common calls short.
"""

from gistream.client import (Client, Session, convergence, look_at, material_change,
                             node_transform, tls_credentials)
from gistream.v1 import gistream_pb2 as pb

__all__ = ["Client", "Session", "convergence", "look_at", "material_change", "node_transform", "pb",
           "tls_credentials"]
