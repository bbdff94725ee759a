"""The Client and Session classes (see the package docstring)."""

import collections
import os
import queue
import threading

import grpc

from gistream.v1 import gistream_pb2 as pb
from gistream.v1 import gistream_pb2_grpc as pb_grpc

_FORMATS = {
    "jpeg": pb.IMAGE_FORMAT_JPEG,
    "png": pb.IMAGE_FORMAT_PNG,
    "exr": pb.IMAGE_FORMAT_EXR,
    "h264": pb.IMAGE_FORMAT_H264,
}


def _vec3(xyz):
    return pb.Vec3(x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2]))


def look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """A CameraChange that looks from `eye` at `target`."""
    return pb.CameraChange(look_at=pb.LookAt(eye=_vec3(eye), target=_vec3(target), up=_vec3(up)))


def node_transform(node, translation=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0),
                   scale=(1.0, 1.0, 1.0)):
    """A NodeTransform: local TRS of node `node` (rotation as x, y, z, w)."""
    x, y, z, w = (float(v) for v in rotation)
    return pb.NodeTransform(node=node, translation=_vec3(translation),
                            rotation=pb.Quat(x=x, y=y, z=z, w=w), scale=_vec3(scale))


def material_change(material, base_color=None, emissive=None, emissive_strength=None,
                    metallic=None, roughness=None):
    """A MaterialChange of material id `material`: only the fields given.
    base_color is linear RGB or RGBA, emissive an RGB factor; metallic and
    roughness are glTF's metallicFactor / roughnessFactor in [0, 1] (GGX;
    metallic 0 with roughness 1 is Lambert)."""
    change = pb.MaterialChange(material=material)
    if base_color is not None:
        change.base_color.extend(float(c) for c in base_color)
    if emissive is not None:
        change.emissive.CopyFrom(_vec3(emissive))
    if emissive_strength is not None:
        change.emissive_strength = float(emissive_strength)
    for name, value in (("metallic", metallic), ("roughness", roughness)):
        if value is None:
            continue
        if not 0.0 <= float(value) <= 1.0:
            raise ValueError(f"{name}: {value} is outside [0, 1]")
        setattr(change, name, float(value))
    return change


_CONVERGENCE = ("refine_samples", "refine_target", "update_complete", "at_rest",
                "frames_since_camera_change", "ms_since_camera_change",
                "frames_since_scene_change", "ms_since_scene_change", "gi_versions_behind",
                "residual", "spp_total")


def convergence(frame):
    """What a frame's picture has converged to, from its stats: a dict of
    those of refine_samples / refine_target (a still view's jittered samples
    per pixel), update_complete (1: the latest GI solution), at_rest, the
    frames and ms since the camera and the scene changed, and the solver's
    gi_versions_behind / residual / spp_total where it reports them."""
    return {k: frame.stats[k] for k in _CONVERGENCE if k in frame.stats}


def _encoding(fmt, quality):
    if fmt not in _FORMATS:
        raise ValueError(f"format: {fmt!r} is not one of {sorted(_FORMATS)}")
    return pb.Encoding(format=_FORMATS[fmt], quality=quality)


def tls_credentials(ca=None, cert=None, key=None):
    """Channel credentials for a gistreamd serving TLS: `ca` the PEM file of
    the CA that signed its certificate (None: the system's roots), `cert` and
    `key` a client certificate for mutual TLS."""
    def read(path):
        if path is None:
            return None
        with open(path, "rb") as f:
            return f.read()
    return grpc.ssl_channel_credentials(read(ca), read(key), read(cert))


class _CallDetails(collections.namedtuple(
        "_CallDetails", ("method", "timeout", "metadata", "credentials", "wait_for_ready",
                         "compression")), grpc.ClientCallDetails):
    pass


class _Bearer(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor,
              grpc.StreamUnaryClientInterceptor, grpc.StreamStreamClientInterceptor):
    """Adds "authorization: Bearer TOKEN" to every call, over TLS and
    loopback plaintext alike (call credentials refuse plaintext)."""

    def __init__(self, token):
        self._header = ("authorization", f"Bearer {token}")

    def _details(self, d):
        return _CallDetails(d.method, d.timeout, tuple(d.metadata or ()) + (self._header,),
                            d.credentials, d.wait_for_ready, d.compression)

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._details(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._details(details), request)

    def intercept_stream_unary(self, continuation, details, requests):
        return continuation(self._details(details), requests)

    def intercept_stream_stream(self, continuation, details, requests):
        return continuation(self._details(details), requests)


class Client:
    """A channel to gistreamd. Errors are grpc.RpcError with the server's
    status code and a message that names the offending field.

    `credentials`: tls_credentials(...) for a server serving TLS; `token`:
    the bearer token of a server started with --auth-tokens (default
    $GISTREAM_TOKEN)."""

    def __init__(self, address="127.0.0.1:50051", timeout=300.0, credentials=None, token=None):
        options = [("grpc.max_receive_message_length", -1),
                   ("grpc.max_send_message_length", -1)]
        self._channel = (grpc.secure_channel(address, credentials, options) if credentials
                         else grpc.insecure_channel(address, options))
        token = token or os.environ.get("GISTREAM_TOKEN")
        if token:
            self._channel = grpc.intercept_channel(self._channel, _Bearer(token))
        self.stub = pb_grpc.GistreamStub(self._channel)
        self.timeout = timeout

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def load_scene(self, name=None, gltf=None):
        """Loads a scene by name (the server's scene directory) or from
        glb / self-contained glTF bytes; returns the LoadSceneResponse."""
        if (name is None) == (gltf is None):
            raise ValueError("load_scene: give exactly one of name or gltf")
        request = pb.LoadSceneRequest(name=name) if name is not None else pb.LoadSceneRequest(gltf=gltf)
        return self.stub.LoadScene(request, timeout=self.timeout)

    def unload_scene(self, scene_id):
        self.stub.UnloadScene(pb.UnloadSceneRequest(scene_id=scene_id), timeout=self.timeout)

    def solvers(self):
        return list(self.stub.ListSolvers(pb.ListSolversRequest(), timeout=self.timeout).solvers)

    def status(self):
        return self.stub.GetServerStatus(pb.GetServerStatusRequest(), timeout=self.timeout)

    def render(self, scene_id, solver="direct", params=None, size=(320, 240), format="png",
               quality=0, camera=None, updates=(), refine_samples=0):
        """One frame (a Frame message; its `image` holds the encoded bytes),
        the mean of `refine_samples` jittered samples per pixel (0: the
        server's default, 16; 1: pixel centres)."""
        request = pb.RenderRequest(scene_id=scene_id, solver=solver,
                                   params={k: str(v) for k, v in (params or {}).items()},
                                   width=size[0], height=size[1],
                                   encoding=_encoding(format, quality), updates=list(updates),
                                   refine_samples=refine_samples)
        if camera is not None:
            request.camera.CopyFrom(camera)
        return self.stub.Render(request, timeout=self.timeout)

    def session(self, scene_id, solver="direct", params=None, size=(320, 240), format="jpeg",
                quality=0, fps=30.0, camera=None, refine_samples=0, frame_budget_ms=0.0):
        """A continuous session (a Session; use it in a with-block). A still
        view refines to `refine_samples` samples per pixel (0: the server's
        default; a frame without updates shades as many as
        `frame_budget_ms` allows, 0: the server's) and then rests; frame
        stats refine_samples / refine_target say how far it got."""
        config = pb.SessionConfig(scene_id=scene_id, solver=solver,
                                  params={k: str(v) for k, v in (params or {}).items()},
                                  width=size[0], height=size[1],
                                  encoding=_encoding(format, quality),
                                  continuous=pb.Continuous(max_fps=fps),
                                  refine_samples=refine_samples,
                                  frame_budget_ms=frame_budget_ms)
        if camera is not None:
            config.camera.CopyFrom(camera)
        return Session(self.stub, config)


class Session:
    """One Session call: `opened` once it runs, `update(...)` sends an
    Update (returns its seq), `frames(n)` yields the next n frames (fewer
    once the view is at rest);
    rejected updates are collected in `rejected`."""

    _END = object()

    def __init__(self, stub, config):
        self._requests = queue.Queue()
        self._requests.put(pb.SessionRequest(config=config))
        self._events = stub.Session(iter(self._requests.get, self._END))
        self._seq = 0
        self.rejected = []
        first = next(self._events)
        if not first.HasField("opened"):
            raise RuntimeError("the server did not open the session")
        self.opened = first.opened
        self._lock = threading.Lock()

    def update(self, camera=None, node=None, light=None, material=None, environment=None):
        """Sends one Update (exactly one kind); returns its sequence number."""
        kinds = {"camera": camera, "node_transform": node, "light": light, "material": material,
                 "environment": environment}
        given = {k: v for k, v in kinds.items() if v is not None}
        if len(given) != 1:
            raise ValueError("update: give exactly one of camera, node, light, material, environment")
        with self._lock:
            self._seq += 1
            seq = self._seq
        update = pb.Update(seq=seq)
        (kind, value), = given.items()
        getattr(update, kind).CopyFrom(value)
        self._requests.put(pb.SessionRequest(update=update))
        return seq

    def frames(self, count, stop_at_rest=True):
        """Yields the next `count` frames (skips events that are not frames).
        With `stop_at_rest` (default) it ends sooner at the first frame that
        says the view is at rest (stats["at_rest"] == 1: the picture is
        finished and changes only with an update; later frames would be
        keep-alives of it, about a second apart)."""
        got = 0
        for event in self._events:
            if event.HasField("rejected"):
                self.rejected.append(event.rejected)
            elif event.HasField("frame"):
                yield event.frame
                got += 1
                if got >= count:
                    return
                if stop_at_rest and event.frame.stats.get("at_rest", 0.0) == 1.0:
                    return

    def close(self):
        """Half-closes the call; the server ends it."""
        self._requests.put(self._END)
        for _ in self._events:  # drain until the server ends the call
            pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
