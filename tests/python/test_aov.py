"""Feature buffers (AOVs) as NumPy arrays: aov=[...] on multiray.render and Renderer."""
import numpy as np
import pytest

import multiray
from conftest import SMALL


def test_aovs_come_as_arrays_of_the_frame_size():
    frames = multiray.render(**SMALL, aov=["albedo", "normal", "depth", "variance"])
    aov = frames[0]["aov"]
    h, w, _ = frames[0]["image"].shape
    assert set(aov) == {"albedo", "normal", "depth", "variance"}
    assert aov["albedo"].shape == (h, w, 3) and aov["albedo"].dtype == np.float32
    assert aov["normal"].shape == (h, w, 3)
    assert aov["depth"].shape == (h, w) and aov["variance"].shape == (h, w)
    # The box with a margin of sky: unit normals and finite depths where a surface was
    # met, a zero normal and an infinite depth where none was; albedo in [0, 1].
    hit = np.isfinite(aov["depth"])
    assert hit.mean() > 0.5 and np.all(aov["depth"][hit] > 0)
    norm = np.linalg.norm(aov["normal"], axis=2)
    assert np.allclose(norm[hit], 1.0, atol=1e-4) and np.all(norm[~hit] == 0)
    assert np.all((aov["albedo"] >= 0) & (aov["albedo"] <= 1))
    assert np.all(aov["variance"] >= 0) and np.any(aov["variance"] > 0)
    # Asking changes no bit of the beauty.
    plain = multiray.render(**SMALL)[0]
    assert "aov" not in plain
    assert np.array_equal(plain["image"].view(np.uint32), frames[0]["image"].view(np.uint32))


def test_a_subset_and_the_cli_form():
    frame = multiray.render(**SMALL, aov="depth,albedo")[0]
    assert set(frame["aov"]) == {"albedo", "depth"}


def test_unknown_names_say_the_nearest():
    with pytest.raises(ValueError, match="did you mean albedo"):
        multiray.render(**SMALL, aov=["albdo"])


def test_emission_is_the_part_of_the_beauty_lights_seen_give():
    frame = multiray.render(**SMALL, aov=["emission", "depth"])[0]
    aov, image = frame["aov"], frame["image"]
    assert set(aov) == {"emission", "depth"}
    assert aov["emission"].shape == image.shape and aov["emission"].dtype == np.float32
    # The sky seen directly is all its pixels' light; the box's walls emit nothing.
    miss = ~np.isfinite(aov["depth"])
    assert np.any(miss) and np.array_equal(aov["emission"][miss], image[miss])
    assert np.all(aov["emission"] >= 0) and np.all(aov["emission"] <= image)
    assert np.mean(aov["emission"][~miss].max(axis=1) == 0) > 0.5
