"""denoise= on multiray.render: the denoised image beside the raw one, as --denoise;
denoise_normal= as --denoise-normal."""
import numpy as np
import pytest

import multiray
from conftest import SMALL


def test_denoised_image_beside_the_raw_one():
    frames = multiray.render(**SMALL, denoise="atrous")
    frame = frames[0]
    assert "denoised" in frame
    den, raw = frame["denoised"], frame["image"]
    assert den.shape == raw.shape and den.dtype == np.float32
    assert np.all(np.isfinite(den)) and not np.array_equal(den, raw)
    # The raw beauty is the one a run without the denoiser makes, bit for bit.
    plain = multiray.render(**SMALL)[0]
    assert "denoised" not in plain
    assert np.array_equal(plain["image"].view(np.uint32), raw.view(np.uint32))
    # Smoother: neighbouring pixels differ less than in the raw image.
    assert np.abs(np.diff(den, axis=1)).mean() < np.abs(np.diff(raw, axis=1)).mean()


def test_a_misspelt_method_is_refused_with_a_suggestion():
    with pytest.raises(ValueError, match="did you mean atrous"):
        multiray.render(**SMALL, denoise="atros")


def test_the_papers_normal_term_is_selectable():
    ours = multiray.render(**SMALL, denoise="atrous")[0]["denoised"]
    papers = multiray.render(**SMALL, denoise="atrous", denoise_normal="svgf")[0]["denoised"]
    # The box's ball is curved: the two normal terms weigh its pixels differently.
    assert not np.array_equal(ours, papers)
    with pytest.raises(ValueError, match="must be turn or svgf"):
        multiray.render(**SMALL, denoise="atrous", denoise_normal="cosine")
