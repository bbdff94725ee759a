"""The Client and Session classes (see the package docstring)."""

import collections
import os
import queue
import threading
import time

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


_CONVERGENCE = ("refine_samples", "refine_target", "refine_carry", "refine_reproject",
                "update_complete", "at_rest",
                "frames_since_camera_change", "ms_since_camera_change",
                "frames_since_scene_change", "ms_since_scene_change", "gi_versions_behind",
                "residual", "spp_total")


def convergence(frame):
    """What a frame's picture has converged to, from its stats: a dict of
    those of refine_samples / refine_target (a still view's jittered samples
    per pixel), refine_carry (> 0: the anti-aliasing of the last complete
    picture carried over a change, its weight in samples), refine_reproject
    (> 0: the picture before a camera move reprojected into the new view,
    its weight in samples), update_complete
    (1: the latest GI solution), at_rest, the frames and ms since the camera and the scene changed, and the solver's
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


class _Headers(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor,
               grpc.StreamUnaryClientInterceptor, grpc.StreamStreamClientInterceptor):
    """Adds headers to every call: "authorization: Bearer TOKEN" (over TLS
    and loopback plaintext alike: call credentials refuse plaintext) and
    "x-gistream-affinity: KEY" (what a balancer hashes)."""

    def __init__(self, headers):
        self._headers = tuple(headers)

    def _details(self, d):
        return _CallDetails(d.method, d.timeout, tuple(d.metadata or ()) + self._headers,
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
    $GISTREAM_TOKEN); `affinity`: sent as x-gistream-affinity on every call
    (default $GISTREAM_AFFINITY), the key a balancer hashes so that a
    scene and its sessions stay on one server."""

    def __init__(self, address="127.0.0.1:50051", timeout=300.0, credentials=None, token=None,
                 affinity=None):
        self._args = dict(address=address, timeout=timeout, credentials=credentials,
                          token=token, affinity=affinity)
        options = [("grpc.max_receive_message_length", -1),
                   ("grpc.max_send_message_length", -1)]
        self._channel = (grpc.secure_channel(address, credentials, options) if credentials
                         else grpc.insecure_channel(address, options))
        token = token or os.environ.get("GISTREAM_TOKEN")
        affinity = affinity or os.environ.get("GISTREAM_AFFINITY")
        headers = ([("authorization", f"Bearer {token}")] if token else []) + (
            [("x-gistream-affinity", affinity)] if affinity else [])
        if headers:
            self._channel = grpc.intercept_channel(self._channel, _Headers(headers))
        self.stub = pb_grpc.GistreamStub(self._channel)
        self.timeout = timeout
        self._loads = {}  # scene id -> its LoadSceneRequest, for sessions that move

    def reconnect(self):
        """A new Client to the same address with the same settings (a
        balancer routes its calls to a server that serves)."""
        return Client(**self._args)

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
        response = self.stub.LoadScene(request, timeout=self.timeout)
        self._loads[response.scene_id] = request
        return response

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
                quality=0, fps=30.0, camera=None, refine_samples=0, frame_budget_ms=0.0,
                resume=True):
        """A continuous session (a Session; use it in a with-block). A still
        view refines to `refine_samples` samples per pixel (0: the server's
        default; a frame without updates shades as many as
        `frame_budget_ms` allows, 0: the server's) and then rests; frame
        stats refine_samples / refine_target say how far it got.

        With `resume` (default) a session on a scene this client loaded
        moves when its server drains (a `draining` event) or goes away: it
        loads the scene again through the same address (a balancer picks a
        server that serves), reopens with the same settings and sends its
        updates again; `moves` lists them."""
        config = pb.SessionConfig(scene_id=scene_id, solver=solver,
                                  params={k: str(v) for k, v in (params or {}).items()},
                                  width=size[0], height=size[1],
                                  encoding=_encoding(format, quality),
                                  continuous=pb.Continuous(max_fps=fps),
                                  refine_samples=refine_samples,
                                  frame_budget_ms=frame_budget_ms)
        if camera is not None:
            config.camera.CopyFrom(camera)
        load = self._loads.get(scene_id) if resume else None
        return Session(self.stub, config, client=self if load is not None else None, load=load)


def update_target_key(update):
    """Updates with the same key set the same fields of the same target: a
    later one makes an earlier one redundant (client/resumable_session.h's
    UpdateTargetKey). None for animation playback (never compacted)."""
    kind = update.WhichOneof("change")
    if kind is None or kind == "animation":
        return None
    change = getattr(update, kind)
    parts = [kind]
    for field, value in change.ListFields():
        parts.append(f"{field.name}={value}" if field.name in ("node", "light", "material")
                     else field.name)
    return tuple(parts)


# The ended calls a session moves after: its server went away (or a proxy
# reset the stream), not a refusal of the request itself.
_MOVABLE = (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.CANCELLED, grpc.StatusCode.INTERNAL,
            grpc.StatusCode.UNKNOWN)


class Session:
    """One Session call: `opened` once it runs, `update(...)` sends an
    Update (returns its seq), `frames(n)` yields the next n frames (fewer
    once the view is at rest);
    rejected updates are collected in `rejected`. A session that can move
    (Client.session's `resume`) records each move in `moves`: (reason,
    seconds from the failure to the new session's first frame)."""

    _END = object()

    def __init__(self, stub, config, client=None, load=None):
        self._config = config
        self._client = client  # set: the session moves (it has the scene's source)
        self._load = load
        self._seq = 0
        self._log = []  # (key, update), compacted: what a move sends again
        self._lock = threading.Lock()
        self._closing = False
        self._clients = []  # the clients of the servers moved to
        self.rejected = []
        self.moves = []
        self._move_started = None
        self._hide_below = 0
        self._open(stub, config)

    def _open(self, stub, config):
        self._requests = queue.Queue()
        self._requests.put(pb.SessionRequest(config=config))
        self._events = stub.Session(iter(self._requests.get, self._END))
        first = next(self._events)
        if not first.HasField("opened"):
            raise RuntimeError("the server did not open the session")
        self.opened = first.opened

    def _move(self, reason):
        """Loads the scene through a new connection, opens the session there
        and sends the logged updates (their sequence numbers kept)."""
        started = time.monotonic()
        deadline = started + 15.0
        delay = 0.1
        while True:
            client = self._client.reconnect()
            try:
                scene = client.load_scene(**({"name": self._load.name}
                                             if self._load.WhichOneof("source") == "name"
                                             else {"gltf": self._load.gltf}))
                config = pb.SessionConfig()
                config.CopyFrom(self._config)
                config.scene_id = scene.scene_id
                old = self._requests
                with self._lock:
                    self._open(client.stub, config)
                    for _, update in self._log:
                        self._requests.put(pb.SessionRequest(update=update))
                    # Frames rendered before the replay shows are not shown.
                    self._hide_below = max((u.seq for _, u in self._log), default=0)
                old.put(self._END)  # the old call ends (its server is leaving)
                self._clients.append(client)
                self._move_started = (reason, started)
                return
            except grpc.RpcError as error:
                client.close()
                if error.code() not in _MOVABLE + (grpc.StatusCode.NOT_FOUND,) or \
                        time.monotonic() + delay > deadline:
                    raise
            time.sleep(delay)
            delay = min(delay * 2, 1.0)

    def _next_event(self):
        """The next event, moving when the server drains or goes away; None
        at the end of the call."""
        while True:
            try:
                event = next(self._events)
            except StopIteration:
                return None
            except grpc.RpcError as error:
                if self._client is None or self._closing or error.code() not in _MOVABLE:
                    raise
                self._move(f"{error.code().name}: {error.details()}")
                continue
            if event.HasField("draining"):
                if self._client is not None and not self._closing:
                    self._move("draining")
                continue
            if event.HasField("frame") and event.frame.last_update_seq < self._hide_below:
                continue  # the new server's, before the replayed updates applied
            if event.HasField("frame"):
                self._hide_below = 0
            if event.HasField("frame") and self._move_started is not None:
                reason, started = self._move_started
                self.moves.append((reason, time.monotonic() - started))
                self._move_started = None
            return event

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
        with self._lock:  # a move replays the log and swaps the call under it
            if self._client is not None:
                key = update_target_key(update)
                if key is not None:
                    self._log = [(k, u) for k, u in self._log if k != key]
                self._log.append((key, update))
            self._requests.put(pb.SessionRequest(update=update))
        return seq

    def frames(self, count, stop_at_rest=True):
        """Yields the next `count` frames (skips events that are not frames).
        With `stop_at_rest` (default) it ends sooner at the first frame that
        says the view is at rest (stats["at_rest"] == 1: the picture is
        finished and changes only with an update; later frames would be
        keep-alives of it, about a second apart)."""
        got = 0
        while (event := self._next_event()) is not None:
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
        self._closing = True
        self._requests.put(self._END)
        for _ in self._events:  # drain until the server ends the call
            pass
        for client in self._clients:
            client.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
