"""The scripting API by job, one module each (api.py re-exports them, as Draft.py does draftmake/); FreeCAD App only: imports objects/, robots/, core/, posts/ and sensors/, never FreeCADGui."""
