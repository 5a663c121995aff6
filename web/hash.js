// The hash of protocol/hash.h that the browser repeats: hash_mix32 (lowbias32), behind the
// per-tree and per-leaf draws of the damage, the debris and the falling leaves, the same bits
// as shaders/common.glsl hash_u.
export function hashMix32(x) {
    x = (x ^ (x >>> 16)) >>> 0;
    x = Math.imul(x, 0x7feb352d) >>> 0;
    x = (x ^ (x >>> 15)) >>> 0;
    x = Math.imul(x, 0x846ca68b) >>> 0;
    return (x ^ (x >>> 16)) >>> 0;
}
