"""The simplified UIC60 (60E1) section of src/mesh/profiles/uic60.rs: its head from the published
arcs, its head depth, foot thickness at the web and web thickness fitted to the published area,
second moment and neutral axis (EN 13674-1). Prints the fitted dimensions (mm) and the
section properties. python validation/uic60_section_fit.py
"""
import numpy as np
from scipy.optimize import fsolve
R1,R2,R3=300.,80.,13.
y1=20.456/2; y2=52.053/2
p1=np.arcsin(y1/R1); p2=np.arcsin((y2-(R1-R2)*np.sin(p1))/R2); p3=np.pi/2-np.arctan(1/20)
C1=np.array([0,-R1]); C2=C1+(R1-R2)*np.array([np.sin(p1),np.cos(p1)]); C3=C2+(R2-R3)*np.array([np.sin(p2),np.cos(p2)])
def arc(C,R,a,b,n=400):
    t=np.linspace(a,b,n); return np.c_[C[0]+R*np.sin(t),C[1]+R*np.cos(t)]
top=np.vstack([arc(C1,R1,0,p1),arc(C2,R2,p1,p2),arc(C3,R3,p2,p3)])
H=172.; TE=11.5
def poly(hh,tf,tw):
    fl=np.array([[36+(hh-14.3)/20,-hh]])
    right=np.vstack([top,fl,[[tw/2,-hh],[tw/2,-(H-tf)],[75,-(H-TE)],[75,-H]]])
    left=right[::-1]*[-1,1]
    return np.vstack([left,right[1:]])  # ccw? check sign
def props(P):
    x,y=P[:,0],P[:,1]; x1,y1=np.roll(x,-1),np.roll(y,-1); c=x*y1-x1*y
    A=c.sum()/2; cy=((y+y1)*c).sum()/(6*A); Iyy=((y*y+y*y1+y1*y1)*c).sum()/12; Izz=((x*x+x*x1+x1*x1)*c).sum()/12
    return A,cy,Iyy-A*cy*cy,Izz
def F(v):
    A,cy,I,Iz=props(poly(*v)); A,I=abs(A),abs(I)
    return [A/7670-1, I/3038.3e4-1, (cy+H)/80.9-1]
v=fsolve(F,[40,25,17]); np.set_printoptions(precision=10); print("head depth, foot thickness, web thickness (mm):",v)
A,cy,I,Iz=np.abs(props(poly(*v))); cy=-cy; print("A (mm^2)",A,"centroid above base (mm)",cy+H,"Iyy (mm^4)",I,"Izz (mm^4)",Iz, "Izz/published",Iz/512.3e4)
v2=fsolve(lambda w:F([w[0],w[1],16.5])[:2],[40,25]); A,cy,I,Iz=props(poly(v2[0],v2[1],16.5)); print("with the web held at 16.5 mm (area and I only):",v2,"centroid",cy+H,"Izz",Iz)
