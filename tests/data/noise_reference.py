#!/usr/bin/env python3
# Independent reference for tests/core/noise_test.cpp: MT19937-64 written out in
# full, uniforms (x >> 11) * 2^-53, normals by Marsaglia's polar method.
# Run: /usr/bin/python3 tests/data/noise_reference.py
import math
class MT64:
    def __init__(self, seed):
        self.mt=[0]*312; self.mt[0]=seed & 0xFFFFFFFFFFFFFFFF
        for i in range(1,312):
            self.mt[i]=(6364136223846793005*(self.mt[i-1]^(self.mt[i-1]>>62))+i)&0xFFFFFFFFFFFFFFFF
        self.i=312
    def next(self):
        if self.i>=312:
            UM=0xFFFFFFFF80000000; LM=0x7FFFFFFF
            for k in range(312):
                x=(self.mt[k]&UM)|(self.mt[(k+1)%312]&LM)
                xa=x>>1
                if x&1: xa^=0xB5026F5AA96619E9
                self.mt[k]=self.mt[(k+156)%312]^xa
            self.i=0
        x=self.mt[self.i]; self.i+=1
        x^=(x>>29)&0x5555555555555555
        x^=(x<<17)&0x71D67FFFEDA60000
        x^=(x<<37)&0xFFF7EEE000000000
        x^=x>>43
        return x&0xFFFFFFFFFFFFFFFF
g=MT64(5489)
for _ in range(9999): g.next()
assert g.next()==9981545732273789042, "standard check value"
def normals(seed,n):
    g=MT64(seed); out=[]
    while len(out)<n:
        u1=(g.next()>>11)*2.0**-53; u2=(g.next()>>11)*2.0**-53
        v1=2*u1-1; v2=2*u2-1; s=v1*v1+v2*v2
        if not (0<s<1): continue
        f=math.sqrt(-2*math.log(s)/s); out+= [v1*f, v2*f]
    return out[:n]
g=MT64(1); print("uniform seed1:", [repr((g.next()>>11)*2.0**-53) for _ in range(3)])
print("normals seed1:", [repr(x) for x in normals(1,6)])
print("normals seed42:", [repr(x) for x in normals(42,4)])
