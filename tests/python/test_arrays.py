"""Images and fields pass between NumPy and tricot without copies; a law at given F."""
import os
import unittest

import numpy as np

import common
import tricot


def speckle(h, w, dx=0.0, dy=0.0, seed=7):
    """A speckle image: 700 Gaussian dots of radius 2 px, its content moved by (dx, dy) px."""
    rng = np.random.default_rng(seed)
    cx, cy = rng.uniform(-5, w + 5, 700), rng.uniform(-5, h + 5, 700)
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    img = np.zeros((h, w))
    for px, py in zip(cx + dx, cy + dy):
        img += np.exp(-((x - px) ** 2 + (y - py) ** 2) / (2 * 2.0 ** 2))
    return img / img.max()


class NoCopies(unittest.TestCase):
    def test_a_frame_is_tricots_own_memory(self):
        frames = tricot.Frames(2, 60, 80)
        a, b = frames[0], frames[0]
        self.assertEqual(a.shape, (60, 80))
        self.assertEqual(a.dtype, np.float32)
        self.assertTrue(np.shares_memory(a, b))
        self.assertFalse(np.shares_memory(frames[0], frames[1]))
        # the array's data pointer is the address of the C++ image's pixels
        self.assertEqual(a.__array_interface__["data"][0], frames.address(0))
        self.assertFalse(a.flags.owndata)
        self.assertIs(a.base, frames)
        # writing the array writes the frame: C++ reads the values written
        a[10, 20] = 3.5
        a[59, 79] = 1.25
        self.assertEqual(frames.sum(0), 4.75)
        self.assertEqual(frames.sum(1), 0.0)

    def test_correlate_reads_the_frames_written_in_place(self):
        h, w, dx, dy = 120, 160, 1.5, -0.75
        frames = tricot.Frames(2, h, w)
        frames[0][:] = speckle(h, w)          # in place: no copy into tricot
        frames[1][...] = speckle(h, w, dx, dy)
        f = tricot.correlate(frames, {"dic": {"subset_size": 21, "step": 10, "order": "first"}},
                             roi=[20, 20, 140, 100])
        self.assertEqual(f["termination"], "completed")
        ok = f["status"][1] == tricot.status_names.index("ok")
        self.assertGreater(ok.sum(), 50)
        # the imposed translation, to the interpolation's bias on a smooth speckle (0.02 px)
        self.assertLess(np.abs(f["u"][1][ok] - dx).max(), 0.02)
        self.assertLess(np.abs(f["v"][1][ok] - dy).max(), 0.02)
        np.testing.assert_array_equal(f["u"][1], f["x"][1] - f["x0"])
        # the fields adopt the buffers they were built in
        self.assertFalse(f["u"].flags.owndata)
        self.assertIsNotNone(f["u"].base)

    def test_a_loaded_image_adopts_the_decoded_buffer(self):
        d = common.scratch("image")
        frames = [os.path.join(d, f"f{k}.png") for k in range(2)]
        # an 8-bit gray PNG written here (struct and zlib: no imaging package needed)
        import struct
        import zlib
        img = (speckle(40, 50) * 255).round().astype(np.uint8)
        raw = b"".join(b"\x00" + row.tobytes() for row in img)
        def chunk(t, data):
            return struct.pack(">I", len(data)) + t + data + struct.pack(">I", zlib.crc32(t + data) & 0xffffffff)
        png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 50, 40, 8, 0, 0, 0, 0)) + \
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
        for f in frames:
            with open(f, "wb") as out:
                out.write(png)
        a = tricot.load_image(frames[0])
        self.assertEqual(a.shape, (40, 50))
        np.testing.assert_array_equal(a, img.astype(np.float32))  # gray levels of the 8-bit file
        self.assertFalse(a.flags.owndata)
        self.assertTrue(a.flags.writeable)
        loaded = tricot.Frames.load(frames)
        np.testing.assert_array_equal(loaded[1], a)
        self.assertEqual(loaded[1].__array_interface__["data"][0], loaded.address(1))


class LawAtF(unittest.TestCase):
    MR = {"type": "mooney_rivlin",
          "mooney_rivlin": {"terms": ["C10", "C20", "C21", "C03"], "values": [0.1, -0.025, 0.015, 0.01]}}

    def test_the_reference_is_stress_free_and_the_tangent_is_dP_dF(self):
        law = tricot.Law(self.MR)
        self.assertEqual(law.coefficients, {"C10": 0.1, "C20": -0.025, "C21": 0.015, "C03": 0.01})
        P, A, _ = law.evaluate(np.eye(2))
        np.testing.assert_allclose(P[0], np.zeros((2, 2)), atol=1e-15)
        rng = np.random.default_rng(3)
        F = np.eye(2) + 0.3 * rng.standard_normal((5, 2, 2))
        F[:, 0, 0] += 0.5
        P, A, lambda3 = law.evaluate(F)
        self.assertEqual((P.shape, A.shape, lambda3.shape), ((5, 2, 2), (5, 2, 2, 2, 2), (5,)))
        h = 1e-6  # central differences: error O(h²) ≈ 1e-12 against P's O(0.1)
        for k in range(2):
            for l in range(2):
                dF = np.zeros((2, 2))
                dF[k, l] = h
                Pp, _, _ = law.evaluate(F + dF, tangent="none")
                Pm, _, _ = law.evaluate(F - dF, tangent="none")
                np.testing.assert_allclose(A[:, :, :, k, l], (Pp - Pm) / (2 * h), rtol=1e-6, atol=1e-9)
        _, M, _ = law.evaluate(F, tangent="matrix")
        np.testing.assert_array_equal(M, A.reshape(5, 4, 4))

    def test_the_law_of_a_case_file_and_new_coefficients(self):
        law = tricot.Law(os.path.join(common.SOURCE, "examples/uniaxial-mooney/case.toml"))
        self.assertEqual(law.name, tricot.Law(self.MR).name)
        P1, _, _ = law.evaluate(np.diag([1.3, 0.9]))
        law.coefficients = {"C10": 0.2, "C20": -0.05, "C21": 0.03, "C03": 0.02}
        P2, _, _ = law.evaluate(np.diag([1.3, 0.9]))
        np.testing.assert_allclose(P2, 2 * P1, rtol=1e-14)  # P is linear in the coefficients
        with self.assertRaises(tricot.ConfigError):
            law.evaluate(np.ones((3, 3)))

    def test_an_orthotropic_law_in_its_material_frame(self):
        # paper14's response surface: no Q is the identity frame; a frame turned by 90° swaps course and
        # wale, so F = diag(a, b) in it gives the forces of diag(b, a) in the identity frame, swapped.
        law = tricot.Law({"type": "response_surface",
                          "response_surface": {"preset": "paper14", "coefficients": [0.1] * 14}})
        F = np.diag([1.2, 1.1])
        P, _, _ = law.evaluate(F)
        P_I, _, _ = law.evaluate(F, Q=np.eye(2))
        np.testing.assert_array_equal(P, P_I)
        self.assertTrue(np.isfinite(P).all())
        turned = np.array([[0.0, -1.0], [1.0, 0.0]])
        P_T, _, _ = law.evaluate(F, Q=turned)
        P_swapped, _, _ = law.evaluate(np.diag([1.1, 1.2]))
        np.testing.assert_allclose(np.diag(P_T[0]), np.diag(P_swapped[0])[::-1], rtol=1e-12)


if __name__ == "__main__":
    unittest.main(verbosity=2)
