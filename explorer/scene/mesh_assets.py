"""The files a mesh file names (an OBJ's ``mtllib`` and ``map_Kd``, a glTF's buffers and
image ``uri``, a PLY's texture) read through the safe reader, and the binary layout of a
glTF checked against the real sizes before trimesh allocates anything.

trimesh opens the files a mesh names itself, through its resolver, and swallows every
error there (a texture it cannot open is silently dropped); :class:`AssetResolver` reads
each through :func:`explorer.safe_files.read_bytes` (a regular file, a size cap, opened
without blocking: a FIFO named by ``mtllib`` is refused at once instead of hanging) and
keeps a one-line warning naming each file it could not give, so the loader can say so.
:func:`check_gltf_layout` refuses a glTF whose buffer views or accessors claim more bytes
than their buffers hold (or, for an accessor without data, more than a mesh may have)
before trimesh would allocate them. :func:`check_textures` bounds every decoded image by
:data:`MAX_TEXTURE_PIXELS` (read from its header, before decoding) and decodes it now, so
a truncated or damaged texture is a warning naming it and the mesh is drawn untextured.
"""

from __future__ import annotations

import base64
import binascii
import os
import struct
from pathlib import Path

from explorer.safe_files import MiB, UserFileError, read_bytes

MAX_TEXTURE_PIXELS = 8192 * 8192
"""Most pixels a texture may claim: 8192² 8-bit RGBA is 256 MB while decoding (it is then
reduced to :data:`explorer.scene.meshes.MAX_TEXTURE_EDGE`); a header claiming more is
refused before a byte of it is decoded."""
MAX_ACCESSOR_BYTES = 512 * MiB
"""Most bytes all the accessors of a glTF may make together: the unpacked-mesh cap of
explorer/scene/mesh_limits.py (a glTF accessor without a buffer is zeros trimesh
allocates from its ``count`` alone)."""

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tga", ".gif", ".tif", ".tiff",
                   ".webp", ".ktx2", ".dds")
_COMPONENT_BYTES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
_TYPE_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9,
                    "MAT4": 16}


def _trimesh_resolver_base():
    from trimesh.resolvers import FilePathResolver

    return FilePathResolver


class AssetResolver:
    """A trimesh resolver of the files a mesh names, relative to the mesh's folder and
    never outside it (trimesh's rule), each read with the safe reader once."""

    def __init__(self, mesh_path: Path):
        self._paths = _trimesh_resolver_base()(str(mesh_path))
        self.file_name = self._paths.file_name
        self.file_path = self._paths.file_path
        self.mesh_path = Path(mesh_path)
        self.warnings: list[str] = []
        self._read: dict[str, bytes] = {}

    def _path(self, name: str) -> Path:
        """The file ``name`` refers to: as written, without a leading slash, or the bare
        file name beside the mesh (trimesh's candidates, in its order)."""
        clean = name.strip()
        try:
            for candidate in (clean, clean.lstrip("/"), Path(clean).name):
                try:
                    path = self._paths.absolute(candidate)
                except ValueError:
                    continue
                if path.exists() or path.is_symlink():
                    return path
            return self._paths.absolute(clean)
        except ValueError:
            link = Path(self._paths.parent) / clean
            where = (f"a symbolic link to {os.readlink(link)[:80]!r}" if link.is_symlink()
                     else "a path")
            raise UserFileError(f"{self.mesh_path}: names {name[:80]!r}, {where} outside "
                                f"the mesh's folder") from None
        except (OSError, RuntimeError) as exc:
            # a name too long; a loop of symbolic links (Path.resolve raises RuntimeError
            # for one before Python 3.13, OSError after)
            reason = (exc.strerror if isinstance(exc, OSError) and exc.strerror else
                      "a loop of symbolic links" if isinstance(exc, RuntimeError) else exc)
            raise UserFileError(f"{self.mesh_path}: names {name[:80]!r}, which cannot be "
                                f"opened ({reason})") from None

    def get(self, name: str) -> bytes:
        if name in self._read:
            return self._read[name]
        is_image = name.strip().lower().endswith(_IMAGE_SUFFIXES)
        kind = "texture" if is_image else "mesh asset"
        try:
            path = self._path(name)
            if not path.exists():
                raise UserFileError(f"{path}: no such file (named by {self.mesh_path})")
            data = read_bytes(path, kind)
            if is_image:
                check_image_header(data, path)
        except UserFileError as exc:
            self.warnings.append(f"{exc}; the {kind} is skipped")
            raise
        self._read[name] = data
        return data

    def __getitem__(self, name: str) -> bytes:
        return self.get(name)

    def __contains__(self, name: str) -> bool:
        try:
            self.get(name)
        except UserFileError:
            return False
        return True

    def namespaced(self, namespace: str) -> AssetResolver:
        return AssetResolver(Path(self._paths.parent) / namespace / self.file_name)

    def keys(self):
        return iter(())

    def write(self, name: str, data) -> None:
        raise UserFileError(f"{name}: the mesh reader writes nothing")


def check_image_header(data: bytes, where: Path | str) -> tuple[int, int]:
    """The (width, height) an image's header claims; :class:`UserFileError` when it is not
    an image Pillow reads, claims more than :data:`MAX_TEXTURE_PIXELS` (checked from the
    header, before anything is decoded) or does not decode whole (truncated, damaged)."""
    import io
    import warnings

    from PIL import Image

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        try:
            with Image.open(io.BytesIO(data)) as image:
                width, height = image.size
                if width * height <= MAX_TEXTURE_PIXELS:
                    # decoded here, where the file's name is known: trimesh drops an
                    # image it cannot decode, and a glTF's or PLY's has no name later
                    image.load()
        except Image.DecompressionBombError:
            raise UserFileError(f"{where}: the image claims more pixels than "
                                f"{MAX_TEXTURE_PIXELS:,} (the most a texture may have)") \
                from None
        except Exception as exc:  # noqa: BLE001 - Pillow raises many types for bad data
            raise UserFileError(f"{where}: not an image Pillow can read "
                                f"({type(exc).__name__}: {str(exc)[:80]})") from None
    if width * height > MAX_TEXTURE_PIXELS:
        raise UserFileError(f"{where}: the image claims {width}×{height} pixels, over the "
                            f"{MAX_TEXTURE_PIXELS:,} a texture may have")
    return width, height


def check_textures(parts, where: Path | str) -> list[str]:
    """Bound and decode every base-colour image of the trimesh meshes ``parts`` (``(name,
    mesh, transform)``); a damaged or oversized one is removed from its material and a
    warning naming it is returned, so the part is drawn with its colour instead."""
    warnings_out, seen = [], {}
    for _, mesh, _ in parts:
        material = getattr(getattr(mesh, "visual", None), "material", None)
        for attribute in ("baseColorTexture", "image"):
            image = getattr(material, attribute, None)
            if image is None:
                continue
            if id(image) not in seen:
                seen[id(image)] = _decoded(image, where)
            problem = seen[id(image)]
            if problem:
                if problem not in warnings_out:
                    warnings_out.append(problem)
                try:
                    setattr(material, attribute, None)
                except Exception:  # noqa: BLE001 - a material that keeps its image
                    pass
    return warnings_out


def _decoded(image, where: Path | str) -> str:
    """Empty when ``image`` (a PIL image, header read) is within the cap and decodes
    whole; else the warning."""
    name = image.info.get("file_path") or getattr(image, "filename", "") or "embedded"
    label = f"{where}: texture {name}"
    width, height = image.size
    if width * height > MAX_TEXTURE_PIXELS:
        return (f"{label} claims {width}×{height} pixels, over the {MAX_TEXTURE_PIXELS:,} a "
                f"texture may have; drawn without it")
    try:
        image.load()
    except Exception as exc:  # noqa: BLE001 - Pillow raises many types for bad data
        return f"{label} is damaged ({type(exc).__name__}: {exc}); drawn without it"
    return ""


# complexity: one branch per glTF rule, all checked before any allocation
def check_gltf_layout(header: dict, buffer_lengths: list[int], where: Path | str) -> None:  # noqa: C901
    """Raise :class:`UserFileError` unless every buffer view lies inside its buffer and
    every accessor inside its buffer view (glTF 2.0 §3.6), and all accessors together
    stay under :data:`MAX_ACCESSOR_BYTES`."""
    def bad(text: str) -> UserFileError:
        return UserFileError(f"{where}: {text}")

    def count_of(table: dict, key: str, default: int | None = None) -> int:
        value = table.get(key, default)
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise bad(f"{key} {value!r} is not a count")
        return value

    buffers = header.get("buffers", [])
    views = header.get("bufferViews", [])
    accessors = header.get("accessors", [])
    if not all(isinstance(x, list) for x in (buffers, views, accessors)):
        raise bad("buffers, bufferViews and accessors must be lists")
    for k, buffer in enumerate(buffers):
        if not isinstance(buffer, dict):
            raise bad(f"buffer {k} is not an object")
        claimed = count_of(buffer, "byteLength")
        if k < len(buffer_lengths) and claimed > buffer_lengths[k]:
            uri = buffer.get("uri")
            named = f" ({uri[:80]})" if isinstance(uri, str) and "base64," not in uri else ""
            raise bad(f"buffer {k}{named} claims {claimed} bytes but holds "
                      f"{buffer_lengths[k]}")
    for k, view in enumerate(views):
        if not isinstance(view, dict):
            raise bad(f"bufferView {k} is not an object")
        index = count_of(view, "buffer")
        if index >= len(buffer_lengths):
            raise bad(f"bufferView {k} names buffer {index}, which does not exist")
        end = count_of(view, "byteOffset", 0) + count_of(view, "byteLength")
        if end > buffer_lengths[index]:
            raise bad(f"bufferView {k} ends at byte {end}, past its buffer's "
                      f"{buffer_lengths[index]}")
        if "byteStride" in view and count_of(view, "byteStride") == 0:
            raise bad(f"bufferView {k} has byteStride 0")
    total = 0
    for k, accessor in enumerate(accessors):
        if not isinstance(accessor, dict):
            raise bad(f"accessor {k} is not an object")
        count = count_of(accessor, "count")
        size = _COMPONENT_BYTES.get(accessor.get("componentType"))
        components = _TYPE_COMPONENTS.get(accessor.get("type"))
        if size is None or components is None:
            raise bad(f"accessor {k} has an unknown componentType or type")
        row = size * components
        total += count * row
        if total > MAX_ACCESSOR_BYTES:
            raise bad(f"the accessors claim more than {MAX_ACCESSOR_BYTES // MiB} MB, the "
                      f"most a mesh may have")
        if "bufferView" not in accessor or count == 0:
            continue
        view_index = count_of(accessor, "bufferView")
        if view_index >= len(views):
            raise bad(f"accessor {k} names bufferView {view_index}, which does not exist")
        view = views[view_index]
        stride = view.get("byteStride", row)
        end = count_of(accessor, "byteOffset", 0) + (count - 1) * stride + row
        if end > view["byteLength"]:
            raise bad(f"accessor {k} claims {count} items ending at byte {end}, past its "
                      f"bufferView's {view['byteLength']}")


def glb_layout(data: bytes, where: Path | str) -> tuple[dict, list[int]]:
    """The JSON chunk and the binary chunk's length of a GLB file (glTF 2.0 §4.4); the
    chunk lengths are checked against the file's."""
    if len(data) < 20:
        raise UserFileError(f"{where}: a GLB file of {len(data)} bytes is shorter than its "
                            f"header")
    magic, _, length = struct.unpack_from("<4sII", data)
    if magic != b"glTF":
        raise UserFileError(f"{where}: not a GLB file (no glTF magic)")
    if length > len(data):
        raise UserFileError(f"{where}: the GLB header claims {length} bytes, the file has "
                            f"{len(data)}")
    json_length, json_type = struct.unpack_from("<II", data, 12)
    if json_type != 0x4E4F534A or 20 + json_length > len(data):
        raise UserFileError(f"{where}: the GLB's JSON chunk is missing or runs past the file")
    header = _json(data[20:20 + json_length], where)
    lengths, at = [], 20 + json_length
    at += -at % 4
    if at + 8 <= len(data):
        bin_length, bin_type = struct.unpack_from("<II", data, at)
        if bin_type == 0x004E4942:
            if at + 8 + bin_length > len(data):
                raise UserFileError(f"{where}: the GLB's binary chunk claims {bin_length} "
                                    f"bytes, past the end of the file")
            lengths.append(bin_length)
    return header, lengths


def gltf_buffer_lengths(header: dict, resolver: AssetResolver, where: Path | str
                        ) -> list[int]:
    """The real length of each buffer of a ``.gltf`` (a data URI decoded, a file read
    through ``resolver``, which keeps it for trimesh)."""
    lengths = []
    for k, buffer in enumerate(header.get("buffers", []) or []):
        uri = buffer.get("uri") if isinstance(buffer, dict) else None
        if not isinstance(uri, str):
            raise UserFileError(f"{where}: buffer {k} has no uri")
        index = uri.find("base64,")
        if index >= 0:
            try:
                lengths.append(len(base64.b64decode(uri[index + 7:])))
            except (binascii.Error, ValueError):
                raise UserFileError(f"{where}: buffer {k}'s data URI is not base64") from None
        else:
            lengths.append(len(resolver.get(uri)))
    return lengths


def _json(data: bytes, where: Path | str) -> dict:
    from explorer.safe_files import decode_text, parse_json

    header = parse_json(decode_text(data, where, "glTF"), where)
    if not isinstance(header, dict):
        raise UserFileError(f"{where}: the glTF JSON is not an object")
    return header


def check_gltf_bytes(data: bytes, suffix: str, resolver: AssetResolver,
                     where: Path | str) -> None:
    """:func:`check_gltf_layout` of a ``.glb`` or ``.gltf`` file's bytes."""
    if suffix == ".glb":
        header, lengths = glb_layout(data, where)
        external = [b for b in header.get("buffers", []) or []
                    if isinstance(b, dict) and "uri" in b]
        if external:        # a GLB may name further buffers by uri after its own
            lengths += gltf_buffer_lengths({"buffers": external}, resolver, where)
    else:
        header = _json(data, where)
        lengths = gltf_buffer_lengths(header, resolver, where)
    try:
        check_gltf_layout(header, lengths, where)
    except (TypeError, KeyError, AttributeError):
        raise UserFileError(f"{where}: the glTF's buffers, views or accessors are not "
                            f"laid out as glTF 2.0 says") from None



def check_stl_bytes(data: bytes, where: Path | str) -> None:
    """A binary STL's triangle count (bytes 80–83) must match its length (84 + 50 per
    triangle); a file that is neither that nor ASCII text starting ``solid`` is refused
    (trimesh would otherwise guess a text encoding for a damaged binary file)."""
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if len(data) == 84 + 50 * count:
            return
    head = data[:1024]
    if head.lstrip().lower().startswith(b"solid") and head.isascii():
        return
    if len(data) < 84:
        raise UserFileError(f"{where}: {len(data)} bytes, shorter than a binary STL's header "
                            f"and not ASCII STL")
    raise UserFileError(f"{where}: not ASCII STL, and as binary STL its header claims "
                        f"{count:,} triangles ({84 + 50 * count:,} bytes) but the file has "
                        f"{len(data):,}")
